// `bitstep record SCENE [--inputs FILE] [--settings JSON] --steps N -o REPLAY` and
// `bitstep verify REPLAY... [--dump-at STEP FILE]` and `bitstep diff A B`.
#pragma once

namespace bitstep {

int record_command(int argc, char** argv, const char* engine_version);
int verify_command(int argc, char** argv);
int diff_command(int argc, char** argv);

}  // namespace bitstep
