// Poses as floats, for drawing only: a renderer wants floats, and between
// two 60 Hz steps a 144 Hz display wants a pose in between. Nothing here
// goes back into the simulation (its state stays exact Q32.32).
#pragma once

#include "core/pose.h"

namespace bitstep {

struct RenderPose {
  float position[3];     // m
  float orientation[4];  // x, y, z, w (a unit quaternion)
};

// The nearest floats to an exact pose.
RenderPose render_pose(const Pose& pose);

// The pose a fraction `alpha` (0..1) of the way from `from` to `to`: the
// position interpolated linearly, the orientation along the shorter arc
// (normalised linear interpolation: it leads or lags slerp by at most
// 0.03 degree for a turn of 30 degrees in the step, 1,800 degrees/s at
// 60 Hz; 0.9 degree for 90). Draw the previous step's pose
// interpolated toward the current one by the time accumulated since it,
// over dt (Glenn Fiedler's "fix your timestep").
RenderPose interpolate(const RenderPose& from, const RenderPose& to, float alpha);

}  // namespace bitstep
