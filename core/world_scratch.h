// What a world keeps from step to step only to reuse memory and exact
// results: the broadphase's and narrowphase's caches, the solver's rows and
// the shock step's workspace, the joints' rows, sleep's scratch. Never state
// (the state hash and snapshots leave it out; a world restored in place
// starts a new one), and internal to core/: core/world.h holds it by pointer,
// so a game that includes the world does not include the solver.
#pragma once

#include <cstdint>
#include <vector>

#include "core/aabb.h"
#include "core/broadphase.h"
#include "core/contact.h"
#include "core/contact_update.h"
#include "core/integrate.h"
#include "core/joint_projection.h"
#include "core/joint_solver.h"
#include "core/joint_tree.h"
#include "core/pose.h"
#include "core/sensor.h"
#include "core/sleep.h"
#include "core/solver.h"
#include "core/tyre_rows.h"

namespace bitstep {

struct WorldScratch {
  std::vector<BroadphaseProxy> proxies;
  std::vector<BodyPair> pairs;
  std::vector<BodyPair> joined, contact_pairs;  // contact_pairs's
  BroadphaseScratch broadphase_scratch;
  std::vector<Contact> previous_contacts;  // workspace of update_contacts
  std::vector<SensorOverlap> previous_overlaps;  // workspace of update_sensor_overlaps
  std::vector<ContactKey> keys_before, sensor_keys_before, keys_after;  // the events' workspace
  std::vector<uint32_t> woken_by_cars;
  std::vector<TyreContact> tyres;     // the cars' grounded wheels this step (drive_cars)
  std::vector<TyreRow> tyre_rows;
  std::vector<Fixed> turn_speed;           // per slot: |w| times the body's reach (m/s), this step
  // Per slot, what find_contacts takes from a body's shapes, which never
  // change while it lives (a slot's next occupant has a new generation):
  // its reach, and its bounds at the pose they were found for. Not state.
  struct ShapeExtent {
    bool known = false;
    uint32_t generation = 0;
    Fixed radius;  // reach (core/envelope.h)
    Pose pose;
    Aabb bounds;   // body_bounds at `pose`
  };
  std::vector<ShapeExtent> shape_extents;
  NarrowphaseCache narrowphase_cache;      // a removed body's entries dropped at once
  InertiaCache inertia_cache;              // the standard pipeline's velocity integration
  PushVelocities push;
  SolverScratch solver_scratch;
  std::vector<JointRow> joint_rows;
  JointTree joint_tree;
  JointProjection joint_projection;  // after the integration (joint_projection.h)
  std::vector<uint8_t> touching;
  SleepScratch sleep_scratch;
  // guendelman: each body's motion before the prediction moved it.
  struct SavedMotion {
    Pose pose;
    Vec3 linear_velocity, angular_velocity, force, torque;
    Pose predicted;  // where contacts were found: the prediction, or the pose itself for a fast body
  };
  std::vector<SavedMotion> before_prediction;
  // Over a step of several substeps: the forces the inputs left pending
  // (each substep integrates them again), and each joint's impulse summed
  // over the substeps (what break_impulse is compared with).
  struct Substeps {
    struct JointImpulse {
      Vec3 point;
      Fixed distance;
    };
    std::vector<BodyRates> forces;  // per slot: force (linear), torque (angular)
    std::vector<JointImpulse> joint_impulses;
  };
  Substeps substeps;
};

}  // namespace bitstep
