// A capsule: the segment from -half_height to +half_height along its local
// y, swept by radius (shape_types.h).
#include "core/ray_primitives.h"
#include "core/shape_types.h"

namespace bitstep {

namespace {

Vec3 capsule_world_axis(const WorldShape& placed) {
  return rotate(placed.pose.orientation, Vec3{Fixed{}, Fixed::one(), Fixed{}});
}

}  // namespace

Fixed CapsuleShape::volume(const Shape& shape) {
  const Fixed r = shape.radius;
  return volume_pi * r * r * (shape.half_height + shape.half_height) + volume_four_thirds_pi * r * r * r;
}

// A cylinder of radius r, length 2h, and two hemispheres:
//   cylinder:    I_yy = m_c r^2 / 2,  I_xx = m_c (r^2 / 4 + (2h)^2 / 12)
//   hemispheres: I_yy = m_s 2 r^2 / 5, I_xx = m_s (2 r^2 / 5 + h^2 + 3 h r / 4)
// (each hemisphere's centre of mass sits 3r/8 beyond the segment end; the
// last term is the parallel-axis shift from its flat face to the capsule's
// centre). Its mass is the parts' (a body sums density times volume).
ShapeMass CapsuleShape::mass(const Shape& shape, Fixed density) {
  const Fixed r = shape.radius, h = shape.half_height;
  const Fixed r2 = r * r;
  const Fixed cylinder = density * volume_pi * r2 * (h + h);
  const Fixed spheres = density * volume_four_thirds_pi * r2 * r;
  const Fixed i_yy = cylinder * r2 / 2.0_fx + spheres * r2 * 2.0_fx / 5.0_fx;
  const Fixed i_xx = cylinder * (r2 / 4.0_fx + h * h / 3.0_fx) +
                     spheres * (r2 * 2.0_fx / 5.0_fx + h * h + h * r * 3.0_fx / 4.0_fx);
  return {cylinder + spheres, Mat33::diagonal({i_xx, i_yy, i_xx}), Vec3{}};
}

Result<void> CapsuleShape::check(const Shape& shape) {
  if (!size_in_envelope(shape.radius)) return Error{"radius", "outside 0.01..50 m"};
  if (shape.half_height < Fixed{} || shape.half_height > envelope::max_size) {
    return Error{"half_height", "outside 0..50 m"};
  }
  return {};
}

Fixed CapsuleShape::extent(const Shape& shape) { return shape.half_height + shape.radius; }

Aabb CapsuleShape::bounds(const WorldShape& placed) {
  const Vec3 axis = abs(rotate(placed.pose.orientation, Vec3{Fixed{}, placed.shape->half_height, Fixed{}}));
  const Fixed r = placed.shape->radius;
  const Vec3 extent = axis + Vec3{r, r, r};
  return {placed.pose.position - extent, placed.pose.position + extent};
}

bool CapsuleShape::ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  ray_primitives::Nearest nearest;
  ray_primitives::cast_capsule(placed.pose.position, capsule_world_axis(placed), placed.shape->half_height,
                               placed.shape->radius + radius, ray, nearest);
  if (nearest.found) entry = nearest.entry;
  return nearest.found;
}

Fixed CapsuleShape::core_radius(const Shape& shape) { return shape.radius; }

// Its core is its segment: the end on d's side.
Vec3 CapsuleShape::core_support(const WorldShape& placed, Vec3 direction) {
  const Vec3 half = rotate(placed.pose.orientation, Vec3{Fixed{}, placed.shape->half_height, Fixed{}});
  return dot(half, direction) < Fixed{} ? placed.pose.position - half : placed.pose.position + half;
}

}  // namespace bitstep
