#include "fixed/vec3.h"

#include "fixed/raw_math.h"

namespace bitstep {

Fixed length(Vec3 v) { return Fixed::from_raw(raw::length3<Wide>(v.x.raw(), v.y.raw(), v.z.raw())); }

Vec3 normalize(Vec3 v) { return normalize_or(v, Vec3::zero()); }

Vec3 normalize_or(Vec3 v, Vec3 fallback) {
  const int64_t in[3] = {v.x.raw(), v.y.raw(), v.z.raw()};
  int64_t out[3] = {};
  if (!raw::normalize<Wide>(in, out, 3)) return fallback;
  return {Fixed::from_raw(out[0]), Fixed::from_raw(out[1]), Fixed::from_raw(out[2])};
}

}  // namespace bitstep
