#include "core/collide.h"

namespace bitstep {

int collide(const WorldShape&, const WorldShape&, Fixed, Manifold& out) {
  out.point_count = 0;
  return 0;
}

}  // namespace bitstep
