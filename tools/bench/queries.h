// `bitstep bench queries`: the cost of the world's queries (core/query.h)
// over 100, 1,000 and 10,000 bodies, as a Markdown table.
#pragma once

namespace bitstep {

int run_bench_queries(int argc, char** argv);

}  // namespace bitstep
