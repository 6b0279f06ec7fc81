#include "replay/thread_pool.h"

namespace bitstep {

namespace {

// Polls done() until it holds or `spin_time` has passed (the clock read
// every 64 polls); whether it held.
template <class Done>
bool spin_until(Done done) {
  const auto until = std::chrono::steady_clock::now() + ThreadPool::spin_time;
  for (int polls = 1;; ++polls) {
    if (done()) return true;
    if (polls % 64 == 0 && std::chrono::steady_clock::now() >= until) return false;
  }
}

}  // namespace

ThreadPool::ThreadPool(int workers) {
  for (int w = 1; w < workers; ++w) threads_.emplace_back([this, w] { serve(w); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_.store(true, std::memory_order_release);
  }
  job_posted_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void ThreadPool::run(Task task, void* context) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = task;
    context_ = context;
    running_.store(static_cast<int>(threads_.size()), std::memory_order_relaxed);
    job_.fetch_add(1, std::memory_order_release);
  }
  job_posted_.notify_all();
  task(context, 0);
  const auto done = [this] { return running_.load(std::memory_order_acquire) == 0; };
  if (spin_until(done)) return;
  std::unique_lock<std::mutex> lock(mutex_);
  job_done_.wait(lock, done);
}

void ThreadPool::serve(int worker) {
  uint64_t seen = 0;
  for (;;) {
    spin_until([&] {
      return job_.load(std::memory_order_acquire) != seen || stopping_.load(std::memory_order_acquire);
    });
    Task task;
    void* context;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_posted_.wait(lock, [&] { return stopping_.load(std::memory_order_relaxed) || job_.load() != seen; });
      if (stopping_.load(std::memory_order_relaxed)) return;
      seen = job_.load(std::memory_order_relaxed);
      task = task_;
      context = context_;
    }
    task(context, worker);
    // The last thread out wakes the caller if it sleeps (under the mutex,
    // so the wake cannot fall between its test and its wait).
    if (running_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      job_done_.notify_one();
    }
  }
}

}  // namespace bitstep
