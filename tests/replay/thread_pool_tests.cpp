// The thread pool runs each job once on every worker, returns only when all
// are done, and sleeps when it has no work (it watches for the next job
// only briefly after each one).
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
