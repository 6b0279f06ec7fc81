#include "replay/thread_pool.h"

namespace bitstep {

ThreadPool::ThreadPool(int workers) {
  for (int w = 1; w < workers; ++w) threads_.emplace_back([this, w] { serve(w); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  job_posted_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void ThreadPool::run(Task task, void* context) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = task;
    context_ = context;
    running_ = static_cast<int>(threads_.size());
    ++job_;
  }
  job_posted_.notify_all();
  task(context, 0);
  std::unique_lock<std::mutex> lock(mutex_);
  job_done_.wait(lock, [this] { return running_ == 0; });
}

void ThreadPool::serve(int worker) {
  uint64_t seen = 0;
  for (;;) {
    Task task;
    void* context;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_posted_.wait(lock, [&] { return stopping_ || job_ != seen; });
      if (stopping_) return;
      seen = job_;
      task = task_;
      context = context_;
    }
    task(context, worker);
    std::lock_guard<std::mutex> lock(mutex_);
    if (--running_ == 0) job_done_.notify_one();
  }
}

}  // namespace bitstep
