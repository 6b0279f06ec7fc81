// `bitstep bench sleep`: ms/step of shipped scenes awake and asleep, as a
// Markdown table (docs/sleeping.md's cost table).
#pragma once

namespace bitstep {

// Options: --quick (stack20 and pyramid20 only), --still (the still method
// instead of motion), --scenes DIR (default "scenes").
int run_bench_sleep(int argc, char** argv);

}  // namespace bitstep
