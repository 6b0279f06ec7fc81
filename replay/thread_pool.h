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
//
// A job's shares are claimed, each by whichever comes first: its own thread,
// or the caller once the caller's share (worker 0) has returned. A step's
// jobs come 0.1-1 ms apart, longer than the spin, so a thread is often
// asleep when a job is posted: the caller then runs the shares the threads
// have not claimed yet instead of waiting ~50 us for them to wake, and two
// workers never take longer than one on a job that one thread does in less
// than a wake-up. Which thread runs a share changes no bit (the shares write
// their own slots, or keep the one-thread order: core/executor.h). The
// caller claims only after its own share has returned, so shares that wait
// for each other's progress still finish: each unclaimed share is claimed
// by its own thread, which waits for nothing else.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
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
  // Whether share `worker` of job `job` is this caller's or thread's to run.
  bool claim(int worker, uint64_t job);

  std::atomic<uint64_t> job_{0};      // jobs posted so far (moved under mutex_)
  std::atomic<int> done_{0};          // shares 1.. of the current job returned
  std::atomic<bool> stopping_{false};  // set under mutex_
  // Per share 1..: the last job it was claimed in.
  std::unique_ptr<std::atomic<uint64_t>[]> claimed_;
};

}  // namespace bitstep
