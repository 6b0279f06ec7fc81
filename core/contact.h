// A contact: the manifold between one shape of body a and one of body b,
// keyed so that it can be matched with last step's (sorted by ids: creation order is the only
// source of simulation order).
#pragma once

#include <cstdint>

#include "core/manifold.h"

namespace bitstep {

struct ContactKey {
  uint32_t body_a, body_b;    // body slot indices, body_a < body_b
  uint16_t shape_a, shape_b;  // shape indices within each body
  friend auto operator<=>(const ContactKey&, const ContactKey&) = default;
};

struct Contact {
  ContactKey key;
  Manifold manifold;
};

}  // namespace bitstep
