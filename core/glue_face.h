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
// each body many times a step). glue_all's are also taken again the next
// step where their inputs stand (shock_solve.cpp, recall_faces).
struct GlueFace {
  enum class State : uint8_t { unmeasured, usable, never };
  State state = State::unmeasured;  // a face is made unmeasured at its first glue of the step
  // glue_all: still holding, where it lies, its body's usable face of the
  // last shock step (GlueFaces::face_at), which may be taken again.
  bool recallable = false;
  uint32_t entry_count = 0;  // glue_all: support contacts (middles and entry_rows)
  Vec3 n, centroid;
  Vec3 e0, e1;  // glue_all: the face's in-plane axes
  Fixed mu, radius, inverse_radius, g00, g01, g11, inverse_det;
  // glue: the bit lengths of the Gram matrix's entries, of inverse_det and
  // of the rocking rows' point shares alpha (the least e with |x| < 2^e).
  int8_t gram_bits = 0, inverse_det_bits = 0, alpha_bits = 0;
  int32_t point_count = 0;
  uint32_t first_point = 0, first_middle = 0;  // into GlueFaces::points and ::middles
  // glue: its target linear velocity, the support's rigid motion at the
  // mover's centroid, from the support's velocity (kept with it) and the
  // row's offsets; and the mover's mass, from its inverse (kept with it).
  bool has_target = false, has_mass = false;
  Vec3 support_linear, support_angular, target_linear;
  Fixed inverse_mass, mass;
};

// What glue_all did: glued, or nothing because the supports do not share
// one rigid motion (they part), or nothing for another reason (their
// contacts do not face one way, or cannot deliver the glue).
enum class GlueAll : uint8_t { refused, glued, supports_part };

// A face point's lever (p - c) x n, and (glue_all) its arm's coordinates
// in the face's plane.
struct GluePoint {
  Vec3 lever;
  Fixed a0, a1;
};

// The step's faces: glue_all's per body slot, glue's per position in the
// shock order, made at their first glue of the step, so that only the faces
// glued take room (a wall glues about one face a brick a step, far fewer
// than its order positions and slots, a face for each of which would take
// megabytes). Workspace: a new step forgets every face by advancing the
// generation, without touching the slots, and hands out faces, points and
// middles from the start of the arrays again. What lies past what this step
// has handed out is last step's, untouched: a step that glues as the last
// one did finds each body's last face, points and middles where it takes
// its new ones, and glue_all takes them again where its inputs are the
// same (shock_solve.cpp, recall_faces): one set of faces, not two.
struct GlueFaces {
  struct Slot {
    uint64_t generation = 0;  // the face at `face` is this step's when equal to GlueFaces::generation
    uint32_t face = 0;
  };
  std::vector<Slot> by_body, by_manifold;
  // Each holds its high-water mark; this step's are the first *_used.
  std::vector<GlueFace> faces;
  std::vector<GluePoint> points;
  std::vector<Vec3> middles;  // glue_all: each support contact's points' mean
  // glue_all: each support contact's ManifoldRow::index, times 2, plus 1
  // where its normal is the face's up (level[a] < level[b]).
  std::vector<uint64_t> entry_rows;
  size_t faces_used = 0, points_used = 0, middles_used = 0;
  uint64_t generation = 1;
  // The solve whose rows this step's faces are measured from, and whether
  // this solve's rows were reused from the one last step's faces were
  // measured from (then ManifoldRow::reused_from names last step's rows).
  uint64_t solve = 0;
  bool recall = false;
  void reset(size_t body_count, size_t manifold_count, uint64_t this_solve, uint64_t rows_reused_from) {
    if (by_body.size() < body_count) by_body.resize(body_count);
    if (by_manifold.size() < manifold_count) by_manifold.resize(manifold_count);
    recall = rows_reused_from != 0 && rows_reused_from == solve;
    solve = this_solve;
    faces_used = points_used = middles_used = 0;
    ++generation;
  }
  // The face of a body slot or an order position, made (not yet measured)
  // if this step has none. Valid until the next face is made.
  GlueFace& of_body(size_t body) { return face_at(by_body[body], true); }
  GlueFace& of_manifold(size_t position) { return face_at(by_manifold[position], false); }
  static bool measured(const GlueFace& face) { return face.state != GlueFace::State::unmeasured; }
  // Room for this step's next `count` points (middles): their first.
  uint32_t take_points(size_t count) { return take(points, points_used, count); }
  uint32_t take_middles(size_t count) {
    if (entry_rows.size() < middles_used + count) entry_rows.resize(middles_used + count);
    return take(middles, middles_used, count);
  }

 private:
  template <typename T>
  static uint32_t take(std::vector<T>& v, size_t& used, size_t count) {
    const size_t first = used;
    used += count;
    if (v.size() < used) v.resize(used);
    return static_cast<uint32_t>(first);
  }
  // A new face goes at faces_used. Where the slot's last face (last step's)
  // lies there, nothing of this step has been written over it or its points
  // and middles (they lie at or past what this step has handed out: the
  // callers check those): it is kept, to be recalled or measured again.
  GlueFace& face_at(Slot& slot, bool keep_last) {
    if (slot.generation != generation) {
      const bool last_here = keep_last && recall && slot.generation + 1 == generation && slot.face == faces_used;
      slot = {generation, take(faces, faces_used, 1)};
      GlueFace& face = faces[slot.face];
      const bool recallable = last_here && face.state == GlueFace::State::usable;
      if (recallable) {
        face.state = GlueFace::State::unmeasured;
        face.recallable = true;
      } else {
        face = GlueFace{};
      }
    }
    return faces[slot.face];
  }
};

}  // namespace bitstep
