#include "tools/bench/scene_specs.h"

#include <cmath>
#include <stdexcept>
#include <variant>

#include "core/convex_hull.h"
#include "core/triangle_mesh.h"
#include "core/world.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "tools/bench/bitstep_engine.h"

namespace bitstep::bench {

namespace {

ShapeSpec to_spec(const Shape& shape) {
  ShapeSpec spec;
  switch (shape.type) {
    case ShapeType::box: spec.kind = ShapeKind::box; break;
    case ShapeType::sphere: spec.kind = ShapeKind::sphere; break;
    case ShapeType::capsule: spec.kind = ShapeKind::capsule; break;
    case ShapeType::plane: break;  // refused by the caller
    case ShapeType::hull: {
      spec.kind = ShapeKind::hull;
      const ConvexHull& hull = *shape.hull;
      for (const Vec3& v : hull.vertices) spec.points.push_back(to_double(v));
      spec.volume = to_double(hull.volume);
      spec.centroid = to_double(hull.centroid);
      for (size_t k = 0; k < 3; ++k) spec.inertia_per_kg[k] = to_double(hull.unit_inertia.rows[k]);
      break;
    }
    case ShapeType::mesh:
    case ShapeType::heightfield: {  // Bullet takes a heightfield's triangles as a mesh
      spec.kind = ShapeKind::mesh;
      for (const Vec3& v : shape.mesh->vertices) spec.points.push_back(to_double(v));
      for (const TriangleMesh::Triangle& t : shape.mesh->triangles) {
        spec.indices.insert(spec.indices.end(), t.corners.begin(), t.corners.end());
      }
      break;
    }
  }
  spec.half_extents = to_double(shape.half_extents);
  spec.radius = to_double(shape.radius);
  spec.half_height = to_double(shape.half_height);
  spec.local_position = to_double(shape.local.position);
  spec.local_orientation = to_double(shape.local.orientation);
  return spec;
}

}  // namespace

void SceneSpecs::add_to(Engine& engine) const {
  for (const BodySpec& body : bodies) engine.add_body(body);
  add_joints(engine);
}

void SceneSpecs::add_joints(Engine& engine) const {
  for (const JointSpec& joint : joints) {
    if (engine.add_joint(joint) < 0) throw std::runtime_error("the engine has no joints");
  }
}

bool specs_from_scene_file(const std::string& path, SceneSpecs& specs, std::string& reason) {
  const Result<Scene> loaded = load_scene_file(path);
  if (!loaded.ok()) {
    reason = loaded.error().message();
    return false;
  }
  return specs_from_scene(loaded.value(), path, specs, reason);
}

bool specs_from_scene(const Scene& scene, const std::string& path, SceneSpecs& out, std::string& reason) {
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) {
    reason = built.error().message();
    return false;
  }
  std::vector<BodySpec>& specs = out.bodies;
  specs.clear();
  out.joints.clear();
  std::vector<int> spec_of(world.bodies().size(), -1);
  for (const Body& body : world.bodies()) {
    if (!body.alive) continue;
    spec_of[static_cast<size_t>(&body - world.bodies().data())] = static_cast<int>(specs.size());
    if (body.type == BodyType::kinematic) {
      reason = path + ": kinematic bodies are not part of the benchmark's body specs";
      return false;
    }
    BodySpec spec;
    spec.is_static = body.type == BodyType::static_body;
    for (const Shape& shape : body.shapes) {
      if (shape.type == ShapeType::plane) {
        reason = path + ": planes are not part of the benchmark's body specs (use a ground box)";
        return false;
      }
      spec.shapes.push_back(to_spec(shape));
    }
    spec.mass = spec.is_static ? 0.0 : 1.0 / to_double(body.inverse_mass);
    spec.position = to_double(body.pose.position);
    spec.orientation = to_double(body.pose.orientation);
    spec.linear_velocity = to_double(body.linear_velocity);
    spec.angular_velocity = to_double(body.angular_velocity);
    spec.static_friction = to_double(body.material.static_friction);
    spec.dynamic_friction = to_double(body.material.dynamic_friction);
    spec.restitution = to_double(body.material.restitution);
    specs.push_back(spec);
  }
  for (const Joint& joint : world.joints()) {
    if (!joint.alive) continue;
    if (joint.type == JointType::max_distance || joint.type == JointType::slider || joint.motor_max != Fixed{}) {
      reason = path + ": ropes, sliders and motors are not part of the benchmark's joint specs";
      return false;
    }
    const Body& a = world.bodies()[joint.body_a];
    JointSpec spec;
    spec.kind = joint.type == JointType::hinge ? JointKind::hinge : joint.type == JointType::cone ? JointKind::cone : JointKind::point;
    spec.body_a = spec_of[joint.body_a];
    spec.body_b = spec_of[joint.body_b];
    spec.anchor = to_double(a.pose.apply(joint.local_anchor_a));
    spec.axis = to_double(rotate(a.pose.orientation, joint.local_axis_a));
    spec.limited = joint.limited;
    spec.lower = to_double(joint.lower_angle);
    spec.upper = to_double(joint.upper_angle);
    spec.swing = to_double(joint.swing_angle);
    spec.friction = to_double(joint.friction_torque);
    out.joints.push_back(spec);
  }
  return true;
}

}  // namespace bitstep::bench
