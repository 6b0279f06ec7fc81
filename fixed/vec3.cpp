#include "fixed/vec3.h"

#include "fixed/raw_math.h"

namespace bitstep {

Fixed length(Vec3 v) { return Fixed::from_raw(raw::length3<Wide>(v.x.raw(), v.y.raw(), v.z.raw())); }

bool length_exceeds(Vec3 v, Fixed limit) {
  if (limit < Fixed{}) return true;
  if (limit == Fixed::max()) return false;  // length saturates at max
  const uint64_t x = magnitude(v.x.raw()), y = magnitude(v.y.raw()), z = magnitude(v.z.raw());
  const uint64_t l = magnitude(limit.raw());
  // S < 3 2^126 and L^2 + L < 2^127: no sum wraps.
  return Wide::mul(x, x) + Wide::mul(y, y) + Wide::mul(z, z) > Wide::mul(l, l) + Wide{l};
}

Vec3 normalize(Vec3 v) { return normalize_or(v, Vec3::zero()); }

Vec3 normalize_or(Vec3 v, Vec3 fallback) {
  const int64_t in[3] = {v.x.raw(), v.y.raw(), v.z.raw()};
  int64_t out[3] = {};
  if (!raw::normalize<Wide>(in, out, 3)) return fallback;
  return {Fixed::from_raw(out[0]), Fixed::from_raw(out[1]), Fixed::from_raw(out[2])};
}

}  // namespace bitstep
