// `bitstep bench fixed`: ns/op of the fixed-point operations next to float and
// double doing the same work, as a Markdown table.
#pragma once

namespace bitstep {

int run_bench_fixed(int argc, char** argv);

}  // namespace bitstep
