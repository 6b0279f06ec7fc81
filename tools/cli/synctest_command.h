// `bitstep synctest SCENE|REPLAY [--frames K] [--steps N]`: GGPO's sync test
// (replay/sync_test.h) on a scene, or on a replay's inputs against its chain.
#pragma once

namespace bitstep {

int synctest_command(int argc, char** argv);

}  // namespace bitstep
