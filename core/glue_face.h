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
  enum class State : uint8_t { unmeasured, usable, never };
  State state = State::unmeasured;  // a face is made unmeasured at its first glue of the step
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
// shock order, made at their first glue of the step, so that only the faces
// glued take room (wall128 glues 8,256 faces a step, one per brick; a face
// of 184 bytes for each of its 24,512 order positions and 8,257 slots took
// 6 MB). Workspace: a new
// step forgets every face by advancing the generation, without touching
// the slots.
struct GlueFaces {
  struct Slot {
    uint64_t generation = 0;  // the face at `face` is this step's when equal to GlueFaces::generation
    uint32_t face = 0;
  };
  std::vector<Slot> by_body, by_manifold;
  std::vector<GlueFace> faces;
  std::vector<GluePoint> points;
  std::vector<Vec3> middles;  // glue_all: each support contact's points' mean
  uint64_t generation = 1;
  void reset(size_t body_count, size_t manifold_count) {
    if (by_body.size() < body_count) by_body.resize(body_count);
    if (by_manifold.size() < manifold_count) by_manifold.resize(manifold_count);
    faces.clear();
    points.clear();
    middles.clear();
    ++generation;
  }
  // The face of a body slot or an order position, made (not yet measured)
  // if this step has none. Valid until the next face is made.
  GlueFace& of_body(size_t body) { return face_at(by_body[body]); }
  GlueFace& of_manifold(size_t position) { return face_at(by_manifold[position]); }
  static bool measured(const GlueFace& face) { return face.state != GlueFace::State::unmeasured; }

 private:
  GlueFace& face_at(Slot& slot) {
    if (slot.generation != generation) {
      slot = {generation, static_cast<uint32_t>(faces.size())};
      faces.emplace_back();
    }
    return faces[slot.face];
  }
};

}  // namespace bitstep
