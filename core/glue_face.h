// The shock step's glue faces (shock_solve.cpp): what the glues compute
// from poses and rows alone, kept through a step. Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "fixed/vec3.h"

namespace bitstep {

// The part of a glue that depends only on poses and rows, which stay as they
// are through the shock step: where the support face's points lie, its
// frame and its least-squares matrix, and whether it can hold at all (no
// row asks the surfaces apart, the normals agree, three points or more not
// on a line). Computed at a face's first glue of the step and kept for the
// passes after it: the same values, so the same bits (a settled pile glues
// each body ~25 times a step).
struct GlueFace {
  enum class State : uint8_t { usable, never };
  State state = State::never;
  uint64_t generation = 0;  // measured in this step when equal to GlueFaces::generation
  Vec3 n, centroid;
  Vec3 e0, e1;  // glue_all: the face's in-plane axes
  Fixed mu, radius, inverse_radius, g00, g01, g11, inverse_det;
  int32_t point_count = 0;
  uint32_t first_point = 0, first_middle = 0;  // into GlueFaces::points and ::middles
};

// A face point's lever (p - c) x n, and (glue_all) its arm's coordinates
// in the face's plane.
struct GluePoint {
  Vec3 lever;
  Fixed a0, a1;
};

// The step's faces: glue_all's per body slot, glue's per position in the
// shock order. Workspace: a new step forgets every face by advancing the
// generation, without touching them.
struct GlueFaces {
  std::vector<GlueFace> by_body, by_manifold;
  std::vector<GluePoint> points;
  std::vector<Vec3> middles;  // glue_all: each support contact's points' mean
  uint64_t generation = 1;
  void reset(size_t body_count, size_t manifold_count) {
    if (by_body.size() < body_count) by_body.resize(body_count);
    if (by_manifold.size() < manifold_count) by_manifold.resize(manifold_count);
    points.clear();
    middles.clear();
    ++generation;
  }
  bool measured(const GlueFace& face) const { return face.generation == generation; }
};

}  // namespace bitstep
