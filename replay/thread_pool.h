// The default executor (core/executor.h): a fixed set of threads that wait
// for jobs. The caller's thread is worker 0, so a pool of n workers starts
// n - 1 threads.
//
// A step posts a few jobs a few hundred microseconds apart (the row setup,
// the iterations, the position passes). Woken through a condition variable,
// a sleeping thread took ~50 us to start an empty job on a 2-core VM, three
// times a step: pyramid20 ran slower on two workers than on one. So a
// thread that finishes a job watches for the next for up to `spin_time`
// before it sleeps on the condition variable, and the caller watches for
// the job's end as long before it sleeps: an idle pool sleeps, and never
// spins longer than that after a job.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "core/executor.h"

namespace bitstep {

class ThreadPool final : public Executor {
 public:
  static constexpr std::chrono::microseconds spin_time{200};

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
  Task task_ = nullptr;               // written under mutex_ before job_ moves
  void* context_ = nullptr;
  std::atomic<uint64_t> job_{0};      // jobs posted so far (moved under mutex_)
  std::atomic<int> running_{0};       // threads still in the current job
  std::atomic<bool> stopping_{false};  // set under mutex_
};

}  // namespace bitstep
