// `bitstep bench` (the suite; `bench fixed` and `bench sleep` are their own files).
#pragma once

namespace bitstep {

// argv: the options after "bench". Returns the process exit code.
int run_bench_suite(int argc, char** argv);

// `bitstep bench headline`: the README's table of headline numbers from a
// report's CSV files (tools/bench/headline.h), written or checked.
int run_bench_headline(int argc, char** argv);

}  // namespace bitstep
