// `bitstep bench` (the suite; `bench fixed` and `bench sleep` are their own files).
#pragma once

namespace bitstep {

// argv: the options after "bench". Returns the process exit code.
int run_bench_suite(int argc, char** argv);

}  // namespace bitstep
