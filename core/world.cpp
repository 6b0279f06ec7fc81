#include "core/world.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <optional>

#include "core/broadphase.h"
#include "core/contact_update.h"
#include "core/integrate.h"
#include "core/joint_types.h"
#include "core/mass.h"
#include "core/query.h"
#include "core/solver.h"
#include "core/world_scratch.h"

namespace bitstep {

namespace {

// The bounds of all of a body's shapes.
Aabb body_bounds(const Body& body) {
  Aabb bounds = shape_aabb({&body.shapes[0], compose(body.pose, body.shapes[0].local)});
  for (size_t s = 1; s < body.shapes.size(); ++s) {
    bounds = bounds.merged(shape_aabb({&body.shapes[s], compose(body.pose, body.shapes[s].local)}));
  }
  return bounds;
}

// The envelope's clamps for its mass and shapes (Body::limits).
void set_speed_limits(Body& body) {
  const Fixed inverse_mass = body.type == BodyType::dynamic ? body.inverse_mass : Fixed{};
  body.limits = speed_limits(inverse_mass, body.shapes, {envelope::max_linear_speed, envelope::max_angular_speed});
}

// a + b for non-negative a, b, at most Fixed::max() (2^31 J): a report,
// not state; computed so that no operation leaves the range (checked build).
Fixed capped_sum(Fixed a, Fixed b) { return a > Fixed::max() - b ? Fixed::max() : a + b; }

// 1/2 m v^2 + 1/2 w . I w (J, the rotational part in body axes), at most
// 2^31 J: a 1e5 kg body at 500 m/s has 1.25e10. m v^2 is taken whole when
// it fits; I is halved until w . I w fits (|w| <= 100 rad/s, entries under
// 2^15 kg m^2) and the result doubled back while it can be. Below 1 kg
// m v^2 <= v^2 fits as it is (max() / m left the range for a 10 g die).
Fixed kinetic_energy(const Body& body) {
  const Fixed mass = Fixed::one() / body.inverse_mass;
  const Fixed speed_sq = length_sq(body.linear_velocity);  // <= 3 x 500^2
  const bool capped = mass > Fixed::one() && speed_sq > Fixed::max() / mass;
  const Fixed linear = capped ? Fixed::max() : mass * speed_sq / 2.0_fx;
  const Vec3 w = rotate_inverse(body.pose.orientation, body.angular_velocity);
  Mat33 inertia = body.inertia_local;
  int halvings = scale_inertia_down(inertia);
  Fixed rotational = dot(w, inertia * w) / 2.0_fx;
  for (; halvings > 0 && rotational <= Fixed::max() / 2.0_fx; --halvings) rotational = rotational * 2.0_fx;
  if (halvings > 0) rotational = Fixed::max();
  return capped_sum(linear, rotational);
}

// a + b within +-2^29 (N s): a joint's impulses summed over the substeps
// stay comparable with its break_impulse, and their length inside the
// range, however large a torn joint's grow (no joint of the envelope
// comes near: 1e5 kg meeting 1,000 m/s is 1e8 N s).
constexpr int64_t summed_impulse_bound = int64_t{1} << 61;  // raw
int64_t within_sum_bound(int64_t raw) { return std::clamp(raw, -summed_impulse_bound, summed_impulse_bound); }
Fixed bounded_sum(Fixed a, Fixed b) {
  return Fixed::from_raw(within_sum_bound(within_sum_bound(a.raw()) + within_sum_bound(b.raw())));
}
Vec3 bounded_sum(Vec3 a, Vec3 b) { return {bounded_sum(a.x, b.x), bounded_sum(a.y, b.y), bounded_sum(a.z, b.z)}; }

// The impulses a joint keeps for the next step's warm start, each
// component within max_joint_impulse, as the state readers require of a
// saved world. The rows hold their accumulations within it as they solve
// (bounded_total); this catches what is set outside them (a slider's
// point impulse projected across its axis). The bound is far above what a
// joint that holds needs, so only a joint that cannot hold is touched.
void keep_joint_impulses_in_bound(std::vector<Joint>& joints) {
  const auto bound = [](Fixed& x) { x = clamp(x, -max_joint_impulse, max_joint_impulse); };
  for (Joint& joint : joints) {
    if (!joint.alive) continue;
    for (Fixed* x : kept_impulses(joint)) bound(*x);
  }
}

}  // namespace

uint64_t WorldInstance::next() {
  static std::atomic<uint64_t> counter{0};
  return ++counter;
}

World::World(const Settings& settings) : settings_(settings), scratch_(std::make_unique<WorldScratch>()) {}
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

SolveContext World::solve_context(const Settings& s) {
  return {s, bodies_, contacts_, {joints_, scratch_->joint_rows, scratch_->joint_tree},
          {scratch_->tyres, scratch_->tyre_rows}, scratch_->push, scratch_->solver_scratch, executor_};
}

uint64_t World::shared_sweep_runs() const { return scratch_->solver_scratch.sweeps.shared_runs; }
uint64_t World::reused_shape_pairs() const { return scratch_->narrowphase_cache.reused; }
uint64_t World::tested_shape_pairs() const { return scratch_->narrowphase_cache.tested; }
uint64_t World::reused_manifold_rows() const { return scratch_->solver_scratch.row_cache.reused; }
uint64_t World::built_manifold_rows() const { return scratch_->solver_scratch.row_cache.built; }
uint64_t World::held_manifold_rows() const { return scratch_->solver_scratch.held_islands.held_rows; }

void World::after_in_place_restore() {
  special_bodies_ = sensor_bodies_ = 0;
  for (Body& body : bodies_) {
    if (!body.alive) continue;
    count_special(body, +1);
    set_speed_limits(body);
  }
  events_.clear();
  // A world built from a state has no caches: the scratch is made anew in
  // place (no allocation; some of it holds atomics and cannot be assigned),
  // keeping what the caller chose of its use.
  const bool reuse = scratch_->solver_scratch.row_cache.enabled;
  const size_t sweep_copies_from = scratch_->solver_scratch.sweep_copies_from;
  std::destroy_at(scratch_.get());
  std::construct_at(scratch_.get());
  if (!reuse) set_contact_reuse(false);
  set_sweep_copies_from(sweep_copies_from);
}

World World::from_state(const Settings& settings, uint64_t step_count, std::vector<Body> bodies,
                        std::vector<uint32_t> free_slots, std::vector<Contact> contacts, std::vector<Joint> joints,
                        std::vector<uint32_t> free_joint_slots, std::vector<SensorOverlap> sensor_overlaps,
                        std::vector<Car> cars, std::vector<Character> characters) {
  World world(settings);
  world.step_count_ = step_count;
  world.bodies_ = std::move(bodies);
  world.free_slots_ = std::move(free_slots);
  world.contacts_ = std::move(contacts);
  world.joints_ = std::move(joints);
  world.free_joint_slots_ = std::move(free_joint_slots);
  world.sensor_overlaps_ = std::move(sensor_overlaps);
  world.cars_ = std::move(cars);
  world.characters_ = std::move(characters);
  for (Body& body : world.bodies_) {
    body.serial = body.alive ? ++world.last_serial_ : 0;
    if (!body.alive) continue;
    world.count_special(body, +1);
    set_speed_limits(body);
  }
  return world;
}

Result<BodyId> World::create_body(const BodyDef& def) {
  if (Result<void> outside = check_envelope(def); !outside.ok()) return outside.error();

  Body body;
  body.type = def.type;
  body.alive = true;
  body.pose = def.pose;
  body.linear_velocity = def.linear_velocity;
  body.angular_velocity = def.angular_velocity;
  body.material = def.material;
  body.filter = def.filter;
  body.sensor = def.sensor;
  body.linear_damping = def.linear_damping;
  body.angular_damping = def.angular_damping;
  body.shapes = def.shapes;
  body.asleep = def.asleep && settings_.sleep_method != SleepMethod::off;
  body.serial = ++last_serial_;
  if (def.type == BodyType::dynamic) {
    // A given mass scales the density: rho = m / V (check_envelope admitted both).
    const MassProperties mass = mass_properties(def.shapes, def.density, def.mass);
    // Re-base the body frame onto the centre of mass: the pose moves to it
    // and the shapes' local positions shift the other way.
    body.pose.position = def.pose.apply(mass.center);
    for (Shape& s : body.shapes) s.local.position -= mass.center;
    body.inverse_mass = Fixed::one() / mass.mass;
    body.inertia_local = mass.inertia;
    body.inverse_inertia_local = inverse(mass.inertia);
    const Mat33 r = rotation(body.pose.orientation);
    body.inverse_inertia_world = r * body.inverse_inertia_local * transpose(r);
  }
  set_speed_limits(body);

  uint32_t index;
  if (!free_slots_.empty()) {
    index = free_slots_.back();
    free_slots_.pop_back();
    body.generation = bodies_[index].generation + 1;
    bodies_[index] = std::move(body);  // remove_body forgot the slot's narrowphase results
  } else {
    index = static_cast<uint32_t>(bodies_.size());
    bodies_.push_back(std::move(body));
  }
  const BodyId id{index, bodies_[index].generation};
  count_special(bodies_[index], +1);
  reset_sleep(settings_, bodies_[index]);
  if (settings_.sleep_method != SleepMethod::off && !bodies_[index].asleep) {
    // A spawn touching sleeping bodies wakes their islands.
    const Aabb reach = body_bounds(bodies_[index]).expanded(settings_.speculative_distance);
    std::vector<uint32_t> touched;
    for (uint32_t i = 0; i < bodies_.size(); ++i) {
      if (bodies_[i].alive && bodies_[i].asleep && body_bounds(bodies_[i]).overlaps(reach)) touched.push_back(i);
    }
    wake_islands_of(touched);
  }
  return id;
}

bool World::is_alive(BodyId id) const {
  return id.index < bodies_.size() && bodies_[id.index].alive && bodies_[id.index].generation == id.generation;
}

void World::forget_narrowphase(uint32_t slot) {
  std::erase_if(scratch_->narrowphase_cache.entries,
                [slot](const NarrowphaseCache::Entry& e) { return e.key.body_a == slot || e.key.body_b == slot; });
}

void World::set_contact_reuse(bool on) {
  scratch_->broadphase_scratch.reuse = on;
  scratch_->broadphase_scratch.last_proxies.clear();
  scratch_->pairs.clear();  // what no proxies give: the pairs and last_proxies agree
  scratch_->narrowphase_cache.enabled = on;
  scratch_->narrowphase_cache.entries.clear();
  scratch_->solver_scratch.row_cache.enabled = on;
  scratch_->solver_scratch.row_cache.entries.clear();
}

void World::set_sweep_copies_from(size_t manifolds) { scratch_->solver_scratch.sweep_copies_from = manifolds; }

void World::count_special(const Body& body, int change) {
  const auto step = static_cast<uint32_t>(change);  // +1 or -1, modulo 2^32
  if (body.filter != CollisionFilter{} || body.sensor) special_bodies_ += step;
  if (body.sensor) sensor_bodies_ += step;
}

bool World::remove_body(BodyId id) {
  if (!is_alive(id)) return false;
  count_special(bodies_[id.index], -1);
  for (uint32_t j = 0; j < joints_.size(); ++j) {
    if (joints_[j].alive && (joints_[j].body_a == id.index || joints_[j].body_b == id.index)) {
      remove_joint({j, joints_[j].generation});
    }
  }
  Body& body = bodies_[id.index];
  body.alive = false;
  body.serial = 0;
  body.shapes.clear();
  free_slots_.push_back(id.index);
  forget_narrowphase(id.index);
  // Sleeping bodies it touched lose a support: they wake (their islands
  // through them), in time to fall in the next step.
  std::vector<uint32_t> touched;
  for (const Contact& c : contacts_) {
    if (c.key.body_a == id.index && bodies_[c.key.body_b].asleep) touched.push_back(c.key.body_b);
    if (c.key.body_b == id.index && bodies_[c.key.body_a].asleep) touched.push_back(c.key.body_a);
  }
  // Contacts of the removed body go now, so a new body in this slot does not inherit them.
  std::erase_if(contacts_, [&](const Contact& c) { return c.key.body_a == id.index || c.key.body_b == id.index; });
  for (Car& car : cars_) {
    if (car.def.chassis.index == id.index) car.alive = false;
  }
  std::erase_if(sensor_overlaps_,
                [&](const SensorOverlap& o) { return o.key.body_a == id.index || o.key.body_b == id.index; });
  wake_islands_of(touched);
  return true;
}

namespace {

// Within twice the body's reach and 1 m more (an anchor's distance from
// the body's centre of mass): a joint's arms then stay within the
// envelope's arms, which bound every solver product.
bool within_joint_reach(Fixed arm, const Body& body) { return arm <= 2.0_fx * reach(body.shapes) + 1.0_fx; }
constexpr const char* reach_reason = "farther from the body than twice its reach and 1 m";

// The point a joint holds on body b: anchor_b (a rope's) or anchor_a (the others').
const Vec3& anchor_on_b(const JointDef& def) {
  return with_joint_type(def.type, [&](auto type) -> const Vec3& { return decltype(type)::anchor_b(def); });
}

// The checks of a JointDef that need no world (World::create_joint's, and
// check_joint_state's of a joint read back): the type's own, then those
// every type shares.
Result<void> check_joint_def(const JointDef& def) {
  // The type's own checks (core/joint_types.h).
  Result<void> own = with_joint_type(def.type, [&](auto type) {
    if (Result<void> refused = decltype(type)::validate(def); !refused.ok()) return refused;
    return decltype(type)::check_motor(def.motor_speed, def.motor_max);
  });
  if (!own.ok()) return own;
  if (def.length < Fixed{} || def.length > 1000.0_fx) return Error{"length", "outside 0..1000 m"};
  if (def.break_impulse < Fixed{}) return Error{"break_impulse", "negative"};
  if (def.friction_torque < Fixed{} || def.friction_torque > 1000000.0_fx) {
    return Error{"friction_torque", "outside 0..1000000 N m"};
  }
  if (def.velocity_iterations > max_joint_iterations || def.position_iterations > max_joint_iterations) {
    return Error{"iterations", "outside 0..1000"};
  }
  return {};
}

}  // namespace

Result<JointId> World::create_joint(const JointDef& def) {
  if (Result<void> refused = joint_error(def); !refused.ok()) return refused.error();
  const Vec3& anchor_b = anchor_on_b(def);
  const Body& a = bodies_[def.body_a.index];
  const Body& b = bodies_[def.body_b.index];
  Joint joint;
  joint.alive = true;
  joint.type = def.type;
  joint.body_a = def.body_a.index;
  joint.body_b = def.body_b.index;
  joint.local_anchor_a = a.pose.apply_inverse(def.anchor_a);
  joint.local_anchor_b = b.pose.apply_inverse(anchor_b);
  joint.length = def.length == Fixed{} ? length(anchor_b - def.anchor_a) : def.length;
  with_joint_type(def.type, [&](auto type) { decltype(type)::make_frames(def, a, b, joint); });
  joint.break_impulse = def.break_impulse;
  joint.friction_torque = def.friction_torque;
  joint.velocity_iterations = def.velocity_iterations;
  joint.position_iterations = def.position_iterations;
  uint32_t index;
  if (!free_joint_slots_.empty()) {
    index = free_joint_slots_.back();
    free_joint_slots_.pop_back();
    joint.generation = joints_[index].generation + 1;
    joints_[index] = joint;
  } else {
    index = static_cast<uint32_t>(joints_.size());
    joints_.push_back(joint);
  }
  const JointId id{index, joints_[index].generation};
  // Joined to an awake body, a sleeping one wakes (its island now moves
  // with it); two sleeping bodies, or one and a static body, stay asleep
  // (a ragdoll built asleep, as JigLib's are).
  if (is_awake_dynamic(bodies_[def.body_a.index]) || is_awake_dynamic(bodies_[def.body_b.index])) {
    wake_islands_of({def.body_a.index, def.body_b.index});
  }
  return id;
}

// create_joint's checks, first refusal first: the type, the bodies, the
// definition, then each anchor's reach.
Result<void> World::joint_error(const JointDef& def) const {
  if (!is_joint_type(def.type)) return Error{"type", "not a joint type"};
  if (!is_alive(def.body_a)) return Error{"body_a", "not a live body"};
  if (!is_alive(def.body_b)) return Error{"body_b", "not a live body"};
  if (def.body_a.index == def.body_b.index) return Error{"body_b", "the same body as body_a"};
  if (bodies_[def.body_a.index].type != BodyType::dynamic && bodies_[def.body_b.index].type != BodyType::dynamic) {
    return Error{"body_b", "neither body is dynamic"};
  }
  if (Result<void> refused = check_joint_def(def); !refused.ok()) return refused;
  const Vec3& anchor_b = anchor_on_b(def);
  const auto beyond = [&](BodyId body, Vec3 anchor) {
    const Body& b = bodies_[body.index];
    return !within_joint_reach(length(anchor - b.pose.position), b);
  };
  if (beyond(def.body_a, def.anchor_a)) return Error{"anchor_a", reach_reason};
  if (beyond(def.body_b, anchor_b)) return Error{&anchor_b == &def.anchor_b ? "anchor_b" : "anchor_a", reach_reason};
  return {};
}

namespace {

// Raw comparisons: a corrupt value reaches no product that saturates.
bool within(Fixed f, Fixed limit) { return f >= -limit && f <= limit; }
bool within(Vec3 v, Fixed limit) { return within(v.x, limit) && within(v.y, limit) && within(v.z, limit); }

// A unit vector as set_axis_frames keeps one: each component within +-2,
// its length squared within 2^-10 of 1.
bool unit_axis(Vec3 v) {
  return within(v, 2.0_fx) && within(length_sq(v) - Fixed::one(), Fixed::from_raw(int64_t{1} << 22));
}

// The frames a joint's type keeps are unit and normal, and those it does
// not keep zero, as create_joint leaves them; the angles likewise.
Result<void> check_joint_frames(const Joint& joint) {
  const bool axes = joint.type == JointType::hinge || joint.type == JointType::cone || joint.type == JointType::slider;
  const bool angles = joint.type == JointType::hinge || joint.type == JointType::cone;
  const struct {
    const Vec3& value;
    const char* field;
  } frames[] = {
      {joint.local_axis_a, "local_axis_a"},
      {joint.local_axis_b, "local_axis_b"},
      {joint.local_reference_a, "local_reference_a"},
      {joint.local_reference_b, "local_reference_b"},
  };
  for (const auto& frame : frames) {
    if (!axes && frame.value != Vec3{}) return Error{frame.field, "not zero on a joint type without axes"};
    if (axes && !unit_axis(frame.value)) return Error{frame.field, "not a unit vector"};
  }
  if (!angles && joint.lower_angle != Fixed{}) {
    return Error{"lower_angle", "not zero on a joint type without angle limits"};
  }
  if (!angles && joint.upper_angle != Fixed{}) {
    return Error{"upper_angle", "not zero on a joint type without angle limits"};
  }
  if (joint.type != JointType::cone && joint.swing_angle != Fixed{}) {
    return Error{"swing_angle", "not zero on a joint type without a cone"};
  }
  if (axes) {
    const Fixed normal = Fixed::from_raw(int64_t{1} << 22);  // |cos| within 2^-10 of right angles
    if (!within(dot(joint.local_axis_a, joint.local_reference_a), normal)) {
      return Error{"local_reference_a", "not normal to local_axis_a"};
    }
    if (!within(dot(joint.local_axis_b, joint.local_reference_b), normal)) {
      return Error{"local_reference_b", "not normal to local_axis_b"};
    }
  }
  return {};
}

// The numbers create_joint checks, as a definition again: limits checked
// whether the joint is limited or not (unlimited, they are zero).
JointDef joint_def_of(const Joint& joint) {
  JointDef def;
  def.type = joint.type;
  def.axis = joint.local_axis_a;
  def.limited = true;
  def.lower_angle = joint.lower_angle;
  def.upper_angle = joint.upper_angle;
  def.swing_angle = joint.swing_angle;
  def.lower_translation = joint.lower_translation;
  def.upper_translation = joint.upper_translation;
  def.motor_speed = joint.motor_speed;
  def.motor_max = joint.motor_max;
  def.break_impulse = joint.break_impulse;
  def.friction_torque = joint.friction_torque;
  def.velocity_iterations = joint.velocity_iterations;
  def.position_iterations = joint.position_iterations;
  return def;
}

// The impulses, each component within max_joint_impulse.
Result<void> check_joint_impulses(const Joint& joint) {
  const Fixed m = max_joint_impulse;
  if (!within(joint.point_impulse, m)) return Error{"point_impulse", "outside +-2^27 N s"};
  if (!within(joint.distance_impulse, m)) return Error{"distance_impulse", "outside +-2^27 N s"};
  if (!within(joint.hinge_impulse[0], m) || !within(joint.hinge_impulse[1], m)) {
    return Error{"hinge_impulse", "outside +-2^27 N m s"};
  }
  if (!within(joint.limit_impulse, m)) return Error{"limit_impulse", "outside +-2^27"};
  if (!within(joint.angular_impulse, m)) return Error{"angular_impulse", "outside +-2^27 N m s"};
  if (!within(joint.motor_impulse, m)) return Error{"motor_impulse", "outside +-2^27"};
  return {};
}

}  // namespace

Result<void> check_joint_state(const Joint& joint, const Body& a, const Body& b) {
  if (Result<void> refused = check_joint_frames(joint); !refused.ok()) return refused;
  if (Result<void> refused = check_joint_def(joint_def_of(joint)); !refused.ok()) return refused;
  // A rope of length 0 took its anchors' distance then: within the
  // envelope's positions and reaches, under 2^16 m.
  if (joint.length < Fixed{} || joint.length > 65536.0_fx) return Error{"length", "outside 0..65536 m"};
  // The anchors within create_joint's reach of their bodies (less 1 mm:
  // the rounding of turning them into the body's frame).
  const Fixed rounding = 0.001_fx;
  if (!within(joint.local_anchor_a, 1024.0_fx) || !within_joint_reach(length(joint.local_anchor_a) - rounding, a)) {
    return Error{"local_anchor_a", reach_reason};
  }
  if (!within(joint.local_anchor_b, 1024.0_fx) || !within_joint_reach(length(joint.local_anchor_b) - rounding, b)) {
    return Error{"local_anchor_b", reach_reason};
  }
  return check_joint_impulses(joint);
}

bool World::is_alive(JointId id) const {
  return id.index < joints_.size() && joints_[id.index].alive && joints_[id.index].generation == id.generation;
}

Result<void> World::set_joint_motor(JointId id, Fixed speed, Fixed max) {
  if (!is_alive(id)) return Error{{}, "not a live joint"};
  Joint& joint = joints_[id.index];
  if (Result<void> refused = check_joint_motor(joint.type, speed, max); !refused.ok()) return refused;
  joint.motor_speed = max > Fixed{} ? speed : Fixed{};  // no motor: nothing of one is kept
  joint.motor_max = max;
  if (max == Fixed{}) joint.motor_impulse = Fixed{};
  // A motor may start a joint at rest: its bodies wake (with their islands).
  wake_islands_of({joint.body_a, joint.body_b});
  return {};
}

bool World::remove_joint(JointId id) {
  if (!is_alive(id)) return false;
  Joint& joint = joints_[id.index];
  const uint32_t a = joint.body_a, b = joint.body_b;
  const uint32_t generation = joint.generation;
  joint = Joint{};  // a dead slot holds nothing but its generation (the state hashes no more)
  joint.generation = generation;
  free_joint_slots_.push_back(id.index);
  std::vector<uint32_t> touched;
  for (uint32_t slot : {a, b}) {
    if (bodies_[slot].alive && bodies_[slot].asleep) touched.push_back(slot);
  }
  wake_islands_of(touched);
  return true;
}

void World::apply_impulse(BodyId id, Vec3 impulse, Vec3 world_point) {
  if (!is_alive(id)) return;
  if (bodies_[id.index].type != BodyType::dynamic) return;
  wake_if_asleep(id.index);
  Body& body = bodies_[id.index];
  add_impulse(body, impulse, world_point, body.limits_in(settings_));
}

void World::apply_force(BodyId id, Vec3 force, Vec3 world_point) {
  if (!is_alive(id)) return;
  wake_if_asleep(id.index);
  add_force(bodies_[id.index], force, world_point, settings_.dt);
}

Result<CarId> World::create_car(const CarDef& def) {
  if (Result<void> refused = check_car(def, bodies_); !refused.ok()) return refused.error();
  Car car;
  car.alive = true;
  car.def = def;
  car.tyre_impulses.assign(def.wheels.size(), TyreImpulse{});
  cars_.push_back(std::move(car));
  return CarId{static_cast<uint32_t>(cars_.size() - 1)};
}

void World::set_car_controls(CarId id, CarControls controls) {
  if (id.index >= cars_.size() || !cars_[id.index].alive) return;
  controls.throttle = clamp(controls.throttle, -Fixed::one(), Fixed::one());
  controls.brake = clamp(controls.brake, Fixed{}, Fixed::one());
  controls.steer = clamp(controls.steer, -Fixed::one(), Fixed::one());
  cars_[id.index].controls = controls;
}

Result<CharacterId> World::create_character(const CharacterDef& def) {
  if (Result<void> refused = check_character(def); !refused.ok()) return refused.error();
  Character c;
  c.def = def;
  c.position = def.position;
  c.facing = def.facing;
  const Fixed reach = def.radius + def.half_height + 1.0_fx;
  const Vec3 r{reach, reach, reach};
  find_character_ground(c, WorldQuery(*this, {c.position - r, c.position + r}), *this);
  characters_.push_back(c);
  return CharacterId{static_cast<uint32_t>(characters_.size() - 1)};
}

void World::set_character_controls(CharacterId id, CharacterControls controls) {
  if (id.index >= characters_.size() || !characters_[id.index].alive) return;
  const Fixed fastest = 100.0_fx;  // m/s, as a body's envelope speed allows
  controls.velocity = {clamp(controls.velocity.x, -fastest, fastest), Fixed{},
                       clamp(controls.velocity.z, -fastest, fastest)};
  characters_[id.index].controls = controls;
}

void World::remove_character(CharacterId id) {
  if (id.index < characters_.size()) characters_[id.index].alive = false;
}

// Each live character's step (core/character.h) over the bodies as they
// now are: the query covers the characters' reach this step.
void World::move_characters() {
  std::optional<Aabb> region;
  for (const Character& c : characters_) {
    if (!c.alive) continue;
    const Fixed reach = c.def.radius + c.def.half_height + c.def.step_height + length(c.velocity) * settings_.dt +
                        length(settings_.gravity) * settings_.dt * settings_.dt + 1.0_fx;
    const Vec3 r{reach, reach, reach};
    const Aabb box{c.position - r, c.position + r};
    region = region ? Aabb{min(region->min, box.min), max(region->max, box.max)} : box;
  }
  if (!region) return;
  const WorldQuery query(*this, *region);
  for (Character& c : characters_) move_character(c, query, *this, settings_.dt);
}

void World::set_velocity(BodyId id, Vec3 linear, Vec3 angular) {
  if (!is_alive(id)) return;
  Body& body = bodies_[id.index];
  if (body.type == BodyType::static_body) return;
  wake_if_asleep(id.index);
  // Clamped now, as the step would: the free-flight step averages the
  // velocity it starts with, which must not be beyond the clamp.
  const SpeedLimits limits = body.limits_in(settings_);
  body.linear_velocity = clamp_speed(linear, limits.linear);
  body.angular_velocity = clamp_speed(angular, limits.angular);
}

void World::wake(BodyId id) {
  if (is_alive(id)) wake_if_asleep(id.index);
}

void World::wake_if_asleep(uint32_t slot) {
  if (bodies_[slot].asleep) wake_islands_of({slot});
}

void World::wake_islands_of(const std::vector<uint32_t>& slots) {
  if (settings_.sleep_method == SleepMethod::off) return;
  bitstep::wake_islands_of(settings_, bodies_, contacts_, joints_, slots);
}

// One step of dt: the physics in substeps of dt / n, then what counts
// steps of dt (sleep, joint breaking, the step counter, the events).
void World::step() {
  events_.clear();
  if (events_on_) touching_before_step();
  if (settings_.substeps == 1) {
    substep(settings_);
  } else {
    run_substeps();
  }
  if (!characters_.empty()) move_characters();
  // Sleep counts steps of dt (its times are rounded to steps, its motion
  // average weights each step by sleep_bias): once per step with the
  // step's settings, on the islands of the last substep.
  if (settings_.sleep_method != SleepMethod::off) sleep_islands(settings_, bodies_, scratch_->sleep_scratch);
  break_joints();
  keep_joint_impulses_in_bound(joints_);
  ++step_count_;
  report_events();
  remove_beyond_bound();
}

// The whole physics over `s.dt`. Cars run in every substep: their wheels
// find the ground from the poses it starts at, and each grounded wheel's
// suspension and tyre join the substep's solve as rows (core/car.h,
// core/tyre_rows.h).
void World::substep(const Settings& s) {
  scratch_->tyres.clear();
  const bool driving = std::any_of(cars_.begin(), cars_.end(), [](const Car& car) { return car.alive; });
  if (driving) {
    scratch_->woken_by_cars.clear();
    drive_cars(WorldQuery(*this, car_region(cars_, bodies_)), s.dt, bodies_, cars_, scratch_->tyres,
               scratch_->woken_by_cars);
    for (const uint32_t slot : scratch_->woken_by_cars) wake_if_asleep(slot);
  }
  std::vector<BodyRates>& start = scratch_->solver_scratch.start_velocities;
  start.resize(bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) start[i] = {bodies_[i].linear_velocity, bodies_[i].angular_velocity};
  if (s.pipeline == Pipeline::guendelman) {
    step_guendelman(s);
  } else {
    step_standard(s);
  }
  if (driving) record_tyre_forces(scratch_->tyres, s.dt, cars_);
  bitstep::integrate_positions(s, bodies_, scratch_->push, scratch_->solver_scratch.start_velocities, contacts_, joints_, scratch_->tyres, scratch_->touching);
  project_joints(s, bodies_, joints_, scratch_->joint_rows, scratch_->joint_projection);
}

// settings_.substeps substeps of dt / n (rounded once: n of them differ
// from dt by less than n / 2 ulp). The forces the inputs left pending act
// in every substep, so a force gives the same impulse over the step as at
// one substep; impulses and set velocities changed the velocities at once,
// before the step, and are not repeated. A breakable joint's impulse over
// the step (the sum of its substeps') is kept for break_joints.
void World::run_substeps() {
  Settings sub = settings_;
  sub.dt = settings_.dt / Fixed::from_int(settings_.substeps);
  WorldScratch::Substeps& held = scratch_->substeps;
  held.forces.resize(bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) held.forces[i] = {bodies_[i].force, bodies_[i].torque};
  held.joint_impulses.assign(joints_.size(), {});
  for (int k = 0; k < settings_.substeps; ++k) {
    if (k > 0) {
      for (size_t i = 0; i < bodies_.size(); ++i) {
        bodies_[i].force = held.forces[i].linear;
        bodies_[i].torque = held.forces[i].angular;
      }
    }
    substep(sub);
    for (size_t j = 0; j < joints_.size(); ++j) {
      if (joints_[j].break_impulse == Fixed{}) continue;
      held.joint_impulses[j].point = bounded_sum(held.joint_impulses[j].point, joints_[j].point_impulse);
      held.joint_impulses[j].distance = bounded_sum(held.joint_impulses[j].distance, joints_[j].distance_impulse);
    }
  }
}

// Joints whose impulse this step went past their break_impulse (an impulse
// per step of dt: over substeps, the sum of theirs, so a steady load or a
// blow breaks a joint whatever the substeps): gone before the next step
// (their bodies wake, as any removal's), each with a joint_broken event
// (listed whether or not events are on: a game must learn its handle died).
void World::break_joints() {
  for (uint32_t j = 0; j < joints_.size(); ++j) {
    if (!joints_[j].alive || joints_[j].break_impulse == Fixed{}) continue;
    Joint over_step = joints_[j];
    if (settings_.substeps > 1) {
      over_step.point_impulse = scratch_->substeps.joint_impulses[j].point;
      over_step.distance_impulse = scratch_->substeps.joint_impulses[j].distance;
    }
    if (!over_break_impulse(over_step)) continue;
    events_.push_back({EventKind::joint_broken, {joints_[j].body_a, joints_[j].body_b, 0, 0}, j});
    remove_joint({j, joints_[j].generation});
  }
}

// The events compare what touches and overlaps before and after the step
// (not each substep: a game sees steps).
void World::touching_before_step() {
  touching_keys(contacts_, scratch_->keys_before);
  scratch_->sensor_keys_before.clear();
  for (const SensorOverlap& o : sensor_overlaps_) scratch_->sensor_keys_before.push_back(o.key);
}

void World::report_events() {
  if (!events_on_) return;
  touching_keys(contacts_, scratch_->keys_after);
  append_changes(scratch_->keys_before, scratch_->keys_after, EventKind::contact_begin, EventKind::contact_end, events_);
  scratch_->keys_after.clear();
  for (const SensorOverlap& o : sensor_overlaps_) scratch_->keys_after.push_back(o.key);
  append_changes(scratch_->sensor_keys_before, scratch_->keys_after, EventKind::sensor_begin, EventKind::sensor_end, events_);
}

void World::step_standard(const Settings& s) {
  bitstep::integrate_velocities(s, bodies_, &scratch_->inertia_cache);
  find_contacts(s);
  if (s.sleep_method != SleepMethod::off) wake_islands(s, bodies_, contacts_, joints_, scratch_->sleep_scratch);
  bitstep::solve_contacts(solve_context(s), SolvePass::standard);
}

// JigLib's order (after Guendelman, Bridson and Fedkiw 2003). Contacts are
// found where this step's forces and velocities would take the bodies (then
// the bodies go back); a collision pass gives restitution on the velocities
// before the forces; the forces come in; an inelastic contact pass and the
// shock step stop what they would push through. A sphere resting on a
// plane: the prediction finds the contact, the collision pass has nothing
// to do (no approach), gravity gives -g dt, the contact pass takes it away,
// and the sphere does not move.
//
// A fast body is not moved for the prediction: its contacts are found where
// it is, kept up to its whole step's motion apart (speculative, as in the
// standard pipeline). Moved a long way, it would be looked for on the far
// side of a thin wall (or past it, finding nothing) and go through.
void World::step_guendelman(const Settings& s) {
  scratch_->before_prediction.resize(bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) {
    Body& body = bodies_[i];
    if (!is_awake_dynamic(body)) continue;
    WorldScratch::SavedMotion& saved = scratch_->before_prediction[i];
    saved = {body.pose, body.linear_velocity, body.angular_velocity, body.force, body.torque, body.pose};
    integrate_velocity(s, body);
    if (moves_far(body, s.dt)) continue;
    body.pose.position = mul_add(body.linear_velocity, s.dt, body.pose.position);
    if (body.angular_velocity != Vec3{}) {
      body.pose.orientation = integrate(body.pose.orientation, body.angular_velocity, s.dt);
    }
    saved.predicted = body.pose;
  }
  find_contacts(s);
  for (size_t i = 0; i < bodies_.size(); ++i) {
    Body& body = bodies_[i];
    if (!is_awake_dynamic(body)) continue;
    const WorldScratch::SavedMotion& saved = scratch_->before_prediction[i];
    body.pose = saved.pose;
    body.linear_velocity = saved.linear_velocity;
    body.angular_velocity = saved.angular_velocity;
    body.force = saved.force;
    body.torque = saved.torque;
    refresh_inverse_inertia(body);  // of the pose the step starts from
  }
  move_contacts_back();
  if (s.sleep_method != SleepMethod::off) wake_islands(s, bodies_, contacts_, joints_, scratch_->sleep_scratch, false);
  bitstep::solve_contacts(solve_context(s), SolvePass::collision);
  bitstep::integrate_velocities(s, bodies_);
  bitstep::solve_contacts(solve_context(s), SolvePass::contact);
}

// Whether a body's motion this step (its centre's, and its farthest point's
// turn) reaches past the envelope's smallest half-size: a prediction that
// far could look for its contacts beyond the far face of the thinnest body
// it may meet (0.02 m thick), where the nearest separating axis points the
// wrong way.
bool World::moves_far(const Body& body, Fixed dt) const {
  const Fixed thinnest = envelope::min_size;
  const Vec3 v = body.linear_velocity, w = body.angular_velocity;
  const Fixed step_speed = length(v) + length(w) * reach(body.shapes);
  return step_speed * dt > thinnest;
}

// The contact points and depths were found at the predicted poses; the
// impulses act on the bodies where they are.
// - A point keeps its place relative to the bodies that moved: shifted back
//   by the prediction's translation of the moving body (the mean of the two
//   when both moved). Otherwise a ball rolling at v would be pushed up at a
//   point v dt ahead of its centre, a lever that brakes the rolling
//   (measured: 5/7 v0 fell to 0.43 v0 at 60 Hz).
// - The depth is the depth at the poses the step starts from. With d_a, d_b
//   the displacement the prediction gave each body's material point at p
//   (d = p - P (P'^-1 p) for start pose P and predicted pose P', rotation
//   included), the overlap along n (from a to b) grew by (d_a - d_b) . n, so
//   depth = depth' - (d_a - d_b) . n. Left at the predicted depth, a body at
//   rest read g dt^2 of overlap it did not have and came to rest that far
//   above its support, and a fast body stopped a step's travel short.
void World::move_contacts_back() {
  const auto displacement = [&](uint32_t slot, Vec3 point) {
    if (!is_awake_dynamic(bodies_[slot])) return Vec3{};
    const WorldScratch::SavedMotion& saved = scratch_->before_prediction[slot];
    if (saved.predicted == saved.pose) return Vec3{};
    return point - saved.pose.apply(saved.predicted.apply_inverse(point));
  };
  const auto shift_of = [&](uint32_t slot) {
    return scratch_->before_prediction[slot].predicted.position - scratch_->before_prediction[slot].pose.position;
  };
  for (Contact& c : contacts_) {
    const bool a_moved = is_awake_dynamic(bodies_[c.key.body_a]);
    const bool b_moved = is_awake_dynamic(bodies_[c.key.body_b]);
    Vec3 shift;
    if (a_moved && b_moved) {
      shift = (shift_of(c.key.body_a) + shift_of(c.key.body_b)) / 2.0_fx;
    } else if (a_moved) {
      shift = shift_of(c.key.body_a);
    } else if (b_moved) {
      shift = shift_of(c.key.body_b);
    }
    Manifold& m = c.manifold;
    for (int i = 0; i < m.point_count; ++i) {
      ContactPoint& p = m.points[static_cast<size_t>(i)];
      const Vec3 closing = displacement(c.key.body_a, p.position) - displacement(c.key.body_b, p.position);
      p.depth -= dot(closing, m.normal);
      p.position -= shift;
    }
  }
}

void World::find_contacts(const Settings& s) {
  scratch_->proxies.clear();
  scratch_->turn_speed.assign(bodies_.size(), Fixed{});
  scratch_->shape_extents.resize(bodies_.size());
  for (uint32_t i = 0; i < bodies_.size(); ++i) {
    const Body& body = bodies_[i];
    if (!body.alive) continue;
    // The reach and bounds found last for this body, or found now (the
    // bounds again only where the pose moved by a bit).
    WorldScratch::ShapeExtent& extent = scratch_->shape_extents[i];
    if (!extent.known || extent.generation != body.generation) {
      extent = {true, body.generation, reach(body.shapes), body.pose, body_bounds(body)};
    } else if (!(extent.pose == body.pose)) {
      extent.pose = body.pose;
      extent.bounds = body_bounds(body);
    }
    // The turn's speed at the farthest point, at most the envelope's linear
    // speed: the margins stay within the motion the envelope bounds (a
    // 0.01 kg compound 87 m across at 100 rad/s would otherwise keep points
    // 140 m apart, whose arms overflow its rows).
    if (body.angular_velocity != Vec3{}) {
      scratch_->turn_speed[i] = min(length(body.angular_velocity) * extent.radius, s.max_linear_speed);
    }
    // Grown by the speculative distance and this step's motion, the turn's
    // included (contact_update.cpp).
    const Fixed margin = s.speculative_distance + (length(body.linear_velocity) + scratch_->turn_speed[i]) * s.dt;
    scratch_->proxies.push_back({i, extent.bounds.expanded(margin), needs_contacts(body)});
  }
  find_pairs(scratch_->proxies, scratch_->pairs, scratch_->broadphase_scratch);
  update_contacts(bodies_, contact_pairs(), s, scratch_->turn_speed, contacts_, scratch_->previous_contacts,
                  scratch_->narrowphase_cache, executor_);
  if (sensor_bodies_ > 0 || !sensor_overlaps_.empty()) update_sensor_overlaps(bodies_, scratch_->pairs, sensor_overlaps_, scratch_->previous_overlaps);
}

// Two bodies joined by a joint do not collide (a chain's links meet at
// their joints; Box2D's collideConnected off), nor two whose collision
// filters keep them apart. The broadphase keeps its pairs for reuse, so
// they are filtered into a copy, and only when there are joints or filters.
const std::vector<BodyPair>& World::contact_pairs() {
  scratch_->joined.clear();
  for (const Joint& j : joints_) {
    if (j.alive) scratch_->joined.push_back({std::min(j.body_a, j.body_b), std::max(j.body_a, j.body_b)});
  }
  if (scratch_->joined.empty() && special_bodies_ == 0) return scratch_->pairs;
  std::sort(scratch_->joined.begin(), scratch_->joined.end());
  scratch_->contact_pairs.clear();
  for (const BodyPair& pair : scratch_->pairs) {
    if (std::binary_search(scratch_->joined.begin(), scratch_->joined.end(), pair)) continue;
    if (!collide_together(bodies_[pair.a].filter, bodies_[pair.b].filter)) continue;
    if (bodies_[pair.a].sensor || bodies_[pair.b].sensor) continue;  // sensors push nothing (core/sensor.h)
    scratch_->contact_pairs.push_back(pair);
  }
  return scratch_->contact_pairs;
}

StepStats World::stats() const {
  StepStats s;
  for (const Body& body : bodies_) {
    if (!body.alive || body.type != BodyType::dynamic) continue;
    if (body.asleep) {
      ++s.sleeping_bodies;
      continue;
    }
    ++s.awake_bodies;
    s.kinetic_energy = capped_sum(s.kinetic_energy, kinetic_energy(body));
  }
  for (const Contact& c : contacts_) {
    s.contact_points += c.manifold.point_count;
    for (int i = 0; i < c.manifold.point_count; ++i) {
      s.max_penetration = max(s.max_penetration, c.manifold.points[static_cast<size_t>(i)].depth);
    }
  }
  return s;
}

}  // namespace bitstep
