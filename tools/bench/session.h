// `bitstep bench session`: what a session (replay/session.h) adds to a
// game's tick, and the largest world each mode sustains at 60 and 20 Hz.
#pragma once

namespace bitstep {

int run_bench_session(int argc, char** argv);

}  // namespace bitstep
