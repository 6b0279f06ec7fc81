#include "replay/render_pose.h"

#include <cmath>

namespace bitstep {

namespace {

// Q32.32 to float: the raw value over 2^32 (exact in double, then rounded once).
float to_float(Fixed value) { return static_cast<float>(static_cast<double>(value.raw()) / 4294967296.0); }

}  // namespace

RenderPose render_pose(const Pose& pose) {
  const Quat& q = pose.orientation;
  return {{to_float(pose.position.x), to_float(pose.position.y), to_float(pose.position.z)},
          {to_float(q.x), to_float(q.y), to_float(q.z), to_float(q.w)}};
}

RenderPose interpolate(const RenderPose& from, const RenderPose& to, float alpha) {
  RenderPose out{};
  for (int i = 0; i < 3; ++i) out.position[i] = from.position[i] + (to.position[i] - from.position[i]) * alpha;
  // q and -q are one rotation: take the one nearer `from` for the shorter arc.
  float dot = 0;
  for (int i = 0; i < 4; ++i) dot += from.orientation[i] * to.orientation[i];
  const float sign = dot < 0 ? -1.0f : 1.0f;
  float length_sq = 0;
  for (int i = 0; i < 4; ++i) {
    out.orientation[i] = from.orientation[i] + (sign * to.orientation[i] - from.orientation[i]) * alpha;
    length_sq += out.orientation[i] * out.orientation[i];
  }
  const float scale = length_sq > 0 ? 1.0f / std::sqrt(length_sq) : 1.0f;
  for (float& c : out.orientation) c *= scale;
  return out;
}

}  // namespace bitstep
