// `bitstep run SCENE [--steps N] [--seconds S] [--hash-every K] [--json]`.
#pragma once

namespace bitstep {

int run_scene_command(int argc, char** argv);

}  // namespace bitstep
