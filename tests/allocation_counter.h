// The allocation tests' executable replaces the global operator new
// (allocation_counter.cpp): every call is counted here.
#pragma once

#include <atomic>

namespace bitstep::test {

extern std::atomic<long> allocations;

}  // namespace bitstep::test
