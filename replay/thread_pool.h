// The default executor (core/executor.h): a fixed set of threads that sleep
// on a condition variable between jobs. The caller's thread is worker 0, so
// a pool of n workers starts n - 1 threads.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "core/executor.h"

namespace bitstep {

class ThreadPool final : public Executor {
 public:
  explicit ThreadPool(int workers);
  ~ThreadPool() override;
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int workers() const override { return static_cast<int>(threads_.size()) + 1; }
  void run(Task task, void* context) override;

 private:
  void serve(int worker);

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable job_posted_, job_done_;
  Task task_ = nullptr;
  void* context_ = nullptr;
  uint64_t job_ = 0;     // jobs posted so far
  int running_ = 0;      // threads still in the current job
  bool stopping_ = false;
};

}  // namespace bitstep
