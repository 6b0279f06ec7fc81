// The engines a peer program offers (tools/bench/peer_main.cpp): defined by
// the file that builds the program (tools/bench/bullet_engine.cpp).
#pragma once

#include <vector>

#include "tools/bench/engine.h"

namespace bitstep::bench {

std::vector<Variant> peer_variants();

}  // namespace bitstep::bench
