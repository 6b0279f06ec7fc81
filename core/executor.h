// How a step runs in parallel. core/ creates no threads: the caller hands
// the world an executor (replay/thread_pool.h is the default one, after
// Box2D v3's task callbacks) and the step gives it work. The result is the
// same bits for any executor and any number of workers (ordered_sweeps.h
// says how).
#pragma once

namespace bitstep {

class Executor {
 public:
  using Task = void (*)(void* context, int worker);
  virtual ~Executor() = default;
  // How many workers run() calls the task for (1: the step stays on the
  // caller's thread and never calls run()).
  virtual int workers() const = 0;
  // Calls task(context, w) once for every w in [0, workers()), on threads of
  // its choosing (the caller's may be one of them), and returns when every
  // call has returned. The calls may wait for each other's progress
  // (ordered_sweeps.h): a thread must not start a call while inside another,
  // and no call may have to wait for another to return before it starts
  // (run one after another on one thread they could never return).
  virtual void run(Task task, void* context) = 0;
};

}  // namespace bitstep
