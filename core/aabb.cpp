#include "core/aabb.h"

#include "core/shape_types.h"

namespace bitstep {

Aabb shape_aabb(const WorldShape& s) {
  return with_shape_type(s.shape->type, [&](auto type) { return decltype(type)::bounds(s); });
}

}  // namespace bitstep
