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

ThreadPool::ThreadPool(int workers)
    : claimed_(std::make_unique<std::atomic<uint64_t>[]>(static_cast<size_t>(workers))) {
  for (int w = 0; w < workers; ++w) claimed_[static_cast<size_t>(w)].store(0, std::memory_order_relaxed);
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

bool ThreadPool::claim(int worker, uint64_t job) {
  std::atomic<uint64_t>& last = claimed_[static_cast<size_t>(worker)];
  uint64_t before = last.load(std::memory_order_acquire);
  return before < job && last.compare_exchange_strong(before, job, std::memory_order_acq_rel);
}

void ThreadPool::run(Task task, void* context) {
  uint64_t job = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = task;
    context_ = context;
    done_.store(0, std::memory_order_relaxed);
    job = job_.fetch_add(1, std::memory_order_release) + 1;
  }
  job_posted_.notify_all();
  task(context, 0);
  const int shares = static_cast<int>(threads_.size());
  for (int w = 1; w <= shares; ++w) {
    if (!claim(w, job)) continue;
    task(context, w);
    done_.fetch_add(1, std::memory_order_acq_rel);
  }
  const auto done = [this, shares] { return done_.load(std::memory_order_acquire) == shares; };
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
    if (!claim(worker, seen)) continue;  // the caller ran this share
    task(context, worker);
    // The last share to return wakes the caller if it sleeps (under the
    // mutex, so the wake cannot fall between its test and its wait).
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == static_cast<int>(threads_.size())) {
      std::lock_guard<std::mutex> lock(mutex_);
      job_done_.notify_one();
    }
  }
}

}  // namespace bitstep
