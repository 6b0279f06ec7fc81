// The world envelope (DESIGN.md, core/README.md "Bodies and mass"): what a
// body definition and an input may hold. Inside it nothing in the simulation
// leaves Q32.32 (a checked build aborts on any saturation: inside the
// envelope that is a bug); outside it a body is refused with the field and
// the reason.
#pragma once

#include <string>

#include "core/body.h"

namespace bitstep {

struct EnvelopeError {
  const char* field = nullptr;   // e.g. "shapes[0].half_extents" is reported as "shapes.half_extents"
  int shape_index = -1;          // which shape, when the field belongs to one
  std::string reason;            // e.g. "outside 0.01..50 m"; empty when the definition is inside
  bool ok() const { return reason.empty(); }
};

// Positions within +-16 km, sizes 0.01..50 m, parts within 50 m of the body
// origin, speeds within the clamps; a dynamic body's mass 0.01..1e5 kg and
// density (given, or mass / volume) at most envelope::max_density.
EnvelopeError check_envelope(const BodyDef& def);

}  // namespace bitstep
