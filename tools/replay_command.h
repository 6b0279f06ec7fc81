// `bitstep record SCENE [--inputs FILE] --steps N -o REPLAY` and
// `bitstep verify REPLAY...`.
#pragma once

namespace bitstep {

int record_command(int argc, char** argv, const char* engine_version);
int verify_command(int argc, char** argv);

}  // namespace bitstep
