// The world envelope check of a body definition (DESIGN.md): positions
// within +-16 km, sizes 0.01..50 m, masses 0.01..1e5 kg. Inside the envelope
// nothing in the solver can overflow; outside it a body is refused.
#pragma once

#include "core/body.h"

namespace bitstep {

struct EnvelopeError {
  const char* field = nullptr;   // e.g. "shapes[0].half_extents" is reported as "shapes.half_extents"
  int shape_index = -1;          // which shape, when the field belongs to one
  const char* reason = nullptr;  // e.g. "outside 0.01..50 m"
  bool ok() const { return reason == nullptr; }
};

EnvelopeError check_envelope(const BodyDef& def);

}  // namespace bitstep
