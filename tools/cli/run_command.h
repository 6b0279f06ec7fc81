// `bitstep run SCENE [--steps N] [--seconds S] [--hash-every K] [--json]
// [--snapshot-at K FILE] [--restore FILE] [--settings JSON]`.
#pragma once

namespace bitstep {

int run_scene_command(int argc, char** argv);

}  // namespace bitstep
