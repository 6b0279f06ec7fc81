// The --threads option of run, record, verify and bench: how many workers
// step the world (replay/thread_pool.h). Not part of the simulation: every
// count gives the same bits.
#pragma once

#include <memory>
#include <string>

#include "replay/thread_pool.h"

namespace bitstep {

constexpr int max_threads = 64;

// Reads a count 1..max_threads; false on anything else.
bool parse_threads(const char* text, int& out);

// A pool of `threads` workers, or null for 1 (the world steps on the
// caller's thread).
std::unique_ptr<ThreadPool> make_pool(int threads);

}  // namespace bitstep
