#include "tools/bench/bitstep_engine.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/convex_hull.h"
#include "core/height_grid.h"
#include "core/triangle_mesh.h"
#include "core/world.h"
#include "replay/state_hash.h"
#include "replay/thread_pool.h"

namespace bitstep::bench {

int64_t to_raw(double value) { return std::llround(std::ldexp(value, 32)); }
double to_double(Fixed value) { return std::ldexp(static_cast<double>(value.raw()), -32); }
V3 to_double(Vec3 v) { return {to_double(v.x), to_double(v.y), to_double(v.z)}; }
Q4 to_double(Quat q) { return {to_double(q.w), to_double(q.x), to_double(q.y), to_double(q.z)}; }

namespace {

Fixed fx(double value) { return Fixed::from_raw(to_raw(value)); }
Vec3 fx(const V3& v) { return {fx(v[0]), fx(v[1]), fx(v[2])}; }
Quat fx(const Q4& q) { return normalize(Quat{fx(q[0]), fx(q[1]), fx(q[2]), fx(q[3])}); }

Shape to_shape(const ShapeSpec& spec) {
  Shape shape;
  switch (spec.kind) {
    case ShapeKind::box: shape.type = ShapeType::box; break;
    case ShapeKind::sphere: shape.type = ShapeType::sphere; break;
    case ShapeKind::capsule: shape.type = ShapeType::capsule; break;
    case ShapeKind::hull: {
      shape.type = ShapeType::hull;
      std::vector<Vec3> points;
      for (const V3& p : spec.points) points.push_back(fx(p));
      auto hull = build_convex_hull(points);
      if (!hull.ok()) throw std::runtime_error("a hull's points: " + hull.error().message());
      shape.hull = hull.value();
      break;
    }
    case ShapeKind::mesh: {
      shape.type = ShapeType::mesh;
      std::vector<Vec3> vertices;
      for (const V3& p : spec.points) vertices.push_back(fx(p));
      auto mesh = build_triangle_mesh(vertices, spec.indices);
      if (!mesh.ok()) throw std::runtime_error("a mesh's arrays: " + mesh.error().message());
      shape.mesh = mesh.value();
      break;
    }
    case ShapeKind::heightfield: {
      shape.type = ShapeType::heightfield;
      HeightGrid grid;
      grid.columns = spec.columns;
      grid.rows = spec.rows;
      grid.spacing_x = fx(spec.spacing_x);
      grid.spacing_z = fx(spec.spacing_z);
      for (const double h : spec.heights) grid.heights.push_back(fx(h));
      auto mesh = build_height_grid_mesh(std::move(grid));
      if (!mesh.ok()) throw std::runtime_error("a heightfield's grid: " + mesh.error().message());
      shape.mesh = mesh.value();
      break;
    }
  }
  shape.half_extents = fx(spec.half_extents);
  shape.radius = fx(spec.radius);
  shape.half_height = fx(spec.half_height);
  shape.local = {fx(spec.local_position), fx(spec.local_orientation)};
  return shape;
}

class BitstepEngine final : public Engine {
 public:
  BitstepEngine(const Settings& settings, int threads) : world_(settings), pool_(threads > 1 ? std::make_unique<ThreadPool>(threads) : nullptr) {
    world_.set_executor(pool_.get());
  }

  int add_body(const BodySpec& spec) override {
    BodyDef def;
    def.type = spec.is_static ? BodyType::static_body : BodyType::dynamic;
    def.pose = {fx(spec.position), fx(spec.orientation)};
    def.linear_velocity = fx(spec.linear_velocity);
    def.angular_velocity = fx(spec.angular_velocity);
    for (const ShapeSpec& s : spec.shapes) def.shapes.push_back(to_shape(s));
    if (!spec.is_static) def.mass = fx(spec.mass);
    def.material = {fx(spec.static_friction), fx(spec.dynamic_friction), fx(spec.restitution)};
    const Result<BodyId> created = world_.create_body(def);
    // Experiments build bodies inside the envelope; one outside is a bug in the experiment.
    if (!created.ok()) throw std::runtime_error("bench body outside the world envelope");
    ids_.push_back(created.value());
    return static_cast<int>(ids_.size()) - 1;
  }

  int add_joint(const JointSpec& spec) override {
    JointDef def;
    def.type = spec.kind == JointKind::hinge ? JointType::hinge
               : spec.kind == JointKind::cone  ? JointType::cone
                                               : JointType::point;
    def.body_a = ids_[static_cast<size_t>(spec.body_a)];
    def.body_b = ids_[static_cast<size_t>(spec.body_b)];
    def.anchor_a = def.anchor_b = fx(spec.anchor);
    def.axis = fx(spec.axis);
    def.limited = spec.limited;
    def.lower_angle = fx(spec.lower);
    def.upper_angle = fx(spec.upper);
    def.swing_angle = fx(spec.swing);
    def.friction_torque = fx(spec.friction);
    const Result<JointId> created = world_.create_joint(def);
    if (!created.ok()) throw std::runtime_error("bench joint: " + created.error().message());
    return joints_++;
  }

  int add_character(const CharacterSpec& spec) override {
    CharacterDef def;
    def.position = fx(spec.position);
    def.radius = fx(spec.radius);
    def.half_height = fx(spec.half_height);
    def.max_slope_cos = fx(std::cos(spec.max_slope));
    def.step_height = fx(spec.step_height);
    const Result<CharacterId> created = world_.create_character(def);
    if (!created.ok()) throw std::runtime_error("bench character: " + created.error().message());
    characters_.push_back(created.value());
    return static_cast<int>(characters_.size()) - 1;
  }

  void walk(int character, const V3& velocity) override {
    world_.set_character_controls(characters_[static_cast<size_t>(character)], {fx(velocity), false});
  }

  V3 character_position(int character) const override {
    return to_double(world_.characters()[characters_[static_cast<size_t>(character)].index].position);
  }

  void step() override { world_.step(); }

  BodyState state(int body) const override {
    const Body& b = world_.body(ids_[static_cast<size_t>(body)]);
    return {to_double(b.pose.position), to_double(b.pose.orientation), to_double(b.linear_velocity),
            to_double(b.angular_velocity)};
  }

  double max_penetration() const override { return to_double(world_.stats().max_penetration); }

  uint64_t state_hash() const override { return bitstep::state_hash(world_); }

 private:
  World world_;
  std::unique_ptr<ThreadPool> pool_;  // null on one thread
  std::vector<BodyId> ids_;
  std::vector<CharacterId> characters_;
  int joints_ = 0;
};

Settings settings_for(const StepConfig& config, Pipeline pipeline, bool shock) {
  Settings settings;
  settings.dt = fx(config.dt);
  settings.velocity_iterations = config.iterations;
  settings.gravity = fx(config.gravity);
  settings.pipeline = pipeline;
  settings.shock_propagation = shock;
  return settings;
}

template <Pipeline pipeline, bool shock>
std::unique_ptr<Engine> make(const StepConfig& config) {
  return std::make_unique<BitstepEngine>(settings_for(config, pipeline, shock), config.threads);
}

// The soft step (core/soft_step.h) at the same passes as the others: each
// substep is two passes (soft, relax), so the sweep's iterations k give
// (k + 1) / 2 substeps (5 at the default 10); the contacts as stiff as the
// substep allows (a quarter of its rate).
std::unique_ptr<Engine> make_soft(const StepConfig& config) {
  Settings settings = settings_for(config, Pipeline::standard, false);
  settings.soft_substeps = std::clamp((config.iterations + 1) / 2, 1, envelope::max_substeps);
  settings.contact_hertz = 1000.0_fx;
  return std::make_unique<BitstepEngine>(settings, config.threads);
}

}  // namespace

const std::vector<Variant>& bitstep_variants() {
  static const std::vector<Variant> variants = {
      {"standard", make<Pipeline::standard, false>},
      {"standard+shock", make<Pipeline::standard, true>},
      {"guendelman", make<Pipeline::guendelman, false>},
      {"guendelman+shock", make<Pipeline::guendelman, true>},
      {"soft", make_soft},
  };
  return variants;
}

}  // namespace bitstep::bench
