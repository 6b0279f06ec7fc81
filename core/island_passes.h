// Solver passes beyond the world's, for the islands whose joints ask for
// them (JointDef::velocity_iterations, position_iterations), as Jolt's
// constraints may: an island runs the most that the world or any of its
// joints asks. Here an island is the awake bodies joined by this solve's
// contact rows and joints; static and sleeping bodies join nothing.
//
// Why: a limb's contact row is a sequential impulse that sees the limb's
// own mass, while its joints are solved exactly (joint_tree.h), which
// spreads each push over the whole ragdoll. The two converge over passes:
// at the world's 10 velocity and 4 position passes a heap of ragdolls keeps
// moving and keeps limbs millimetres inside each other (ragdoll generator:
// replay/generators.h sets its passes).
//
// The extra passes run after the world's (velocity) and before them
// (position, so that the last position pass stays the world's: position_passes.cpp
// pushes jointed bodies one way there), over the island's rows alone, in
// the order of the world's passes: friction, the centroid rows, rocking,
// the free point rows, then its joints. Other islands keep their bits: a
// world with no such joint computes exactly what it did. Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

namespace bitstep {

struct JointRow;
struct JointTree;
struct ManifoldRow;
struct PointRow;
struct Settings;
struct SolverBody;

struct IslandPasses {
  // A row (manifold or point row index) and its island's passes beyond the
  // world's; only rows whose island has some are listed, in row order.
  struct Entry {
    uint32_t index;
    uint16_t extra;
  };
  std::vector<Entry> manifolds, free_rows, push_rows;
  int most_velocity = 0, most_position = 0;  // the largest extra of any island
  // Workspace: the union-find's parents and each root's extras, per slot.
  std::vector<uint32_t> parent;
  std::vector<uint16_t> root_velocity, root_position;
};

// Finds each island's extra passes and lists its rows; sets each joint
// row's extra_velocity_passes and extra_position_passes. Leaves `out` with
// most_velocity = most_position = 0 (and lists nothing) when no joint asks
// for more than the world.
void plan_island_passes(const Settings& settings, const std::vector<SolverBody>& bodies,
                        const std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifold_rows,
                        std::vector<JointRow>& joint_rows, IslandPasses& out);

// The velocity passes beyond the world's (after the world's).
void run_extra_velocity_passes(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows,
                               const std::vector<ManifoldRow>& manifold_rows, std::vector<JointRow>& joint_rows,
                               JointTree& tree, const IslandPasses& plan);

// The position passes beyond the world's (before the world's).
void run_extra_position_passes(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                               std::vector<JointRow>& joint_rows, JointTree& tree, const IslandPasses& plan);

}  // namespace bitstep
