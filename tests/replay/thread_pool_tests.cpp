// The thread pool runs each job's shares once each, returns only when all
// are done, finishes shares that wait for each other's progress whichever
// thread claims them, and sleeps when it has no work (it watches for the
// next job only briefly after each one).
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <ctime>
#include <thread>
#include <vector>

#include "replay/thread_pool.h"

using namespace bitstep;

namespace {

struct Tally {
  std::vector<std::atomic<int>> runs;  // per worker
  std::atomic<int> total{0};
  explicit Tally(int workers) : runs(static_cast<size_t>(workers)) {}
};

void count(void* context, int worker) {
  Tally& tally = *static_cast<Tally*>(context);
  tally.runs[static_cast<size_t>(worker)].fetch_add(1, std::memory_order_relaxed);
  tally.total.fetch_add(1, std::memory_order_relaxed);
}

double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

// Shares that wait for each other, as the ordered sweeps do: share w waits
// until share `waits_for(w)` has started (-1: for nothing).
struct Chain {
  std::vector<std::atomic<int>> started;
  int (*waits_for)(int worker, int workers);
  int workers;
  explicit Chain(int n, int (*rule)(int, int)) : started(static_cast<size_t>(n)), waits_for(rule), workers(n) {}
};

void chained(void* context, int worker) {
  Chain& chain = *static_cast<Chain*>(context);
  chain.started[static_cast<size_t>(worker)].store(1, std::memory_order_release);
  const int other = chain.waits_for(worker, chain.workers);
  if (other < 0) return;
  while (chain.started[static_cast<size_t>(other)].load(std::memory_order_acquire) == 0) std::this_thread::yield();
}

}  // namespace

TEST_CASE("every worker runs every job once, and run returns after all of them", "[threads]") {
  for (const int workers : {1, 2, 8}) {
    INFO(workers << " workers");
    ThreadPool pool(workers);
    Tally tally(workers);
    constexpr int jobs = 5000;
    for (int job = 1; job <= jobs; ++job) {
      pool.run(count, &tally);
      // Every worker's run of this job is counted when run returns.
      REQUIRE(tally.total.load() == job * workers);
    }
    for (const std::atomic<int>& runs : tally.runs) CHECK(runs.load() == jobs);
  }
}

TEST_CASE("an idle thread pool sleeps instead of spinning", "[threads]") {
  ThreadPool pool(2);
  Tally tally(2);
  pool.run(count, &tally);
  // A worker spinning for 300 ms would use ~300 ms of CPU time; one that
  // sleeps after ThreadPool::spin_time (0.2 ms) uses almost none.
  const double before = process_cpu_ms();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double used = process_cpu_ms() - before;
  CHECK(used < 50.0);
  // And it wakes for the next job.
  pool.run(count, &tally);
  CHECK(tally.total.load() == 4);
}

TEST_CASE("shares that wait for each other finish, the threads asleep or awake when a job comes", "[threads]") {
  // Share 0 (the caller's) waits for the last share; or each share for the
  // one before it; or share 1 for share 0 (run after it, on any thread).
  const auto last = [](int worker, int workers) { return worker == 0 ? workers - 1 : -1; };
  const auto previous = [](int worker, int) { return worker - 1; };
  const auto first = [](int worker, int) { return worker == 1 ? 0 : -1; };
  for (const int workers : {2, 3, 8}) {
    for (int (*rule)(int, int) : {+last, +previous, +first}) {
      ThreadPool pool(workers);
      for (int job = 0; job < 40; ++job) {
        INFO(workers << " workers, job " << job);
        // Every other job after a pause past spin_time: the threads asleep.
        if (job % 2 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        Chain chain(workers, rule);
        pool.run(chained, &chain);
        for (const std::atomic<int>& started : chain.started) REQUIRE(started.load() == 1);
      }
    }
  }
}
