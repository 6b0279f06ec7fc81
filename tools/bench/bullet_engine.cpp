// The peer engine: Bullet's btDiscreteDynamicsWorld behind tools/bench/engine.h,
// single-threaded, with Bullet's defaults except where the benchmark needs the
// same model as bitstep (noted below).
//
// Precision: Debian's `bullet` pkg-config module is single precision (btScalar
// is float; the double build is the separate `bullet-float64` module, which
// defines BT_USE_DOUBLE_PRECISION). The libraries' symbols carry the scalar
// type (stepSimulation(float, int, float)), so headers and library agree.
//
// Bullet defaults kept (btContactSolverInfo, Bullet 3.24):
//   - contacts push overlap out at m_erp2 = 0.2 per step (m_erp is for
//     joints), no slop (m_linearSlop = 0), m_globalCfm = 0; split impulse is
//     on but only for overlaps deeper than 4 cm
//     (m_splitImpulsePenetrationThreshold = -0.04): a shallower overlap is
//     pushed out by Baumgarte on the real velocity, which adds energy (a
//     bouncing ball rebounds higher than restitution alone gives);
//   - warm starting with factor 0.85; solver mode SOLVER_USE_WARMSTARTING |
//     SOLVER_SIMD: ONE friction row per contact point, along the sliding
//     direction (an arbitrary tangent when not sliding), not two;
//   - restitution only above 0.2 m/s approach (m_restitutionVelocityThreshold);
//   - collision margins: sphere and capsule use their radius as the margin (no
//     inflation); btBoxShape keeps its margin (0.04 m, or 10% of the smallest
//     half extent if less) INSIDE the given half extents, so the box's
//     geometry is exactly the half extents (box-box and box-sphere use the
//     sharp box; GJK pairs such as box-capsule round its edges by the margin);
//   - contact points persist until they separate beyond the contact-breaking
//     threshold, up to 4 per manifold; no CCD; the implicit gyroscopic term
//     (BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY) on every body.
// Set here: iterations, gravity, zero damping, zero rolling/spinning friction,
// no deactivation (the benchmark runs without sleep), and the pair rules.
#include <BulletCollision/CollisionDispatch/btGhostObject.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletDynamics/Character/btKinematicCharacterController.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "tools/bench/bitstep_engine.h"
#include "tools/bench/peer.h"

namespace bitstep::bench {

namespace {

btScalar bt(double value) { return static_cast<btScalar>(value); }
btVector3 bt(const V3& v) { return {bt(v[0]), bt(v[1]), bt(v[2])}; }
btQuaternion bt(const Q4& q) { return btQuaternion(bt(q[1]), bt(q[2]), bt(q[3]), bt(q[0])).normalized(); }
double dbl(btScalar value) { return static_cast<double>(value); }
V3 dbl(const btVector3& v) { return {dbl(v.x()), dbl(v.y()), dbl(v.z())}; }

// bitstep's pair rules (core/body.h): friction sqrt(mu_a mu_b), restitution
// max(e_a, e_b). Bullet's defaults are the products. Bullet calls these when
// a contact point is added to a manifold.
btScalar combined_friction(const btCollisionObject* a, const btCollisionObject* b) {
  return btSqrt(a->getFriction() * b->getFriction());
}
btScalar combined_restitution(const btCollisionObject* a, const btCollisionObject* b) {
  return btMax(a->getRestitution(), b->getRestitution());
}

// A shape's volume and its inertia per unit mass about its own centre, in its
// own axes: the formulas of core/mass.cpp. (Bullet's own calculateLocalInertia
// is exact for boxes and spheres but takes the bounding box for capsules and
// compounds, which would give Bullet different bodies than bitstep's.)
struct ShapeMass {
  double volume;
  V3 inertia_per_kg;  // the diagonal (a hull's whole tensor is its spec's)
};

ShapeMass shape_mass(const ShapeSpec& s) {
  constexpr double pi = 3.14159265358979323846;
  switch (s.kind) {
    case ShapeKind::box: {
      const double x = s.half_extents[0] * s.half_extents[0];
      const double y = s.half_extents[1] * s.half_extents[1];
      const double z = s.half_extents[2] * s.half_extents[2];
      return {8 * s.half_extents[0] * s.half_extents[1] * s.half_extents[2], {(y + z) / 3, (x + z) / 3, (x + y) / 3}};
    }
    case ShapeKind::sphere: {
      const double i = 0.4 * s.radius * s.radius;
      return {4 * pi / 3 * s.radius * s.radius * s.radius, {i, i, i}};
    }
    case ShapeKind::capsule: {
      // A cylinder of length 2h and two hemispheres, along y.
      const double r = s.radius, h = s.half_height, r2 = r * r;
      const double cylinder = pi * r2 * 2 * h, spheres = 4 * pi / 3 * r2 * r, v = cylinder + spheres;
      const double i_yy = cylinder * r2 / 2 + spheres * r2 * 0.4;
      const double i_xx = cylinder * (r2 / 4 + h * h / 3) + spheres * (r2 * 0.4 + h * h + h * r * 0.75);
      return {v, {i_xx / v, i_yy / v, i_xx / v}};
    }
    case ShapeKind::hull: return {s.volume, {0, 0, 0}};
    case ShapeKind::mesh:
    case ShapeKind::heightfield: return {0, {0, 0, 0}};  // static only
  }
  return {0, {0, 0, 0}};
}

// btBvhTriangleMeshShape with the arrays it reads kept beside it.
class MeshShape final : public btBvhTriangleMeshShape {
 public:
  explicit MeshShape(const ShapeSpec& s) : MeshShape(arrays_of(s)) {}

 private:
  struct Arrays {
    std::vector<btScalar> vertices;
    std::vector<int> indices;
    std::unique_ptr<btTriangleIndexVertexArray> view;
  };
  static std::shared_ptr<Arrays> arrays_of(const ShapeSpec& s) {
    auto a = std::make_shared<Arrays>();
    for (const V3& p : s.points) a->vertices.insert(a->vertices.end(), {bt(p[0]), bt(p[1]), bt(p[2])});
    for (const uint32_t i : s.indices) a->indices.push_back(static_cast<int>(i));
    a->view = std::make_unique<btTriangleIndexVertexArray>(
        static_cast<int>(a->indices.size() / 3), a->indices.data(), static_cast<int>(3 * sizeof(int)),
        static_cast<int>(s.points.size()), a->vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
    return a;
  }
  explicit MeshShape(std::shared_ptr<Arrays> a) : btBvhTriangleMeshShape(a->view.get(), true), arrays_(std::move(a)) {}
  std::shared_ptr<Arrays> arrays_;
};

// btHeightfieldTerrainShape over its own copy of the heights. Bullet
// centres the grid on its bounding box (x and z from 0 to (n - 1) spacing,
// y from the lowest height to the highest), so the terrain is the child of
// a compound shape, moved back to put sample (0, 0) at the shape's origin.
class HeightfieldShape final : public btCompoundShape {
 public:
  explicit HeightfieldShape(const ShapeSpec& s) : btCompoundShape(false, 1) {
    heights_.reserve(s.heights.size());
    for (const double h : s.heights) heights_.push_back(static_cast<float>(h));
    const auto [lowest, highest] = std::minmax_element(heights_.begin(), heights_.end());
    terrain_ = std::make_unique<btHeightfieldTerrainShape>(static_cast<int>(s.columns), static_cast<int>(s.rows),
                                                           heights_.data(), *lowest, *highest, 1, false);
    terrain_->setLocalScaling(btVector3(bt(s.spacing_x), 1, bt(s.spacing_z)));
    const btVector3 centre(bt(0.5 * (s.columns - 1) * s.spacing_x), (*lowest + *highest) / 2,
                           bt(0.5 * (s.rows - 1) * s.spacing_z));
    addChildShape(btTransform(btQuaternion::getIdentity(), centre), terrain_.get());
  }

 private:
  std::vector<float> heights_;
  std::unique_ptr<btHeightfieldTerrainShape> terrain_;
};

std::unique_ptr<btCollisionShape> make_shape(const ShapeSpec& s) {
  switch (s.kind) {
    case ShapeKind::box: return std::make_unique<btBoxShape>(bt(s.half_extents));
    case ShapeKind::sphere: return std::make_unique<btSphereShape>(bt(s.radius));
    // btCapsuleShape(radius, height): height is the inner segment, along local y.
    case ShapeKind::capsule: return std::make_unique<btCapsuleShape>(bt(s.radius), bt(2 * s.half_height));
    // Bullet grows a hull by its collision margin: 1 mm here (its default,
    // 4 cm, would make a 0.5 m die 8% larger).
    case ShapeKind::hull: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (const V3& p : s.points) hull->addPoint(bt(p), false);
      hull->recalcLocalAabb();
      hull->setMargin(btScalar(0.001));
      return hull;
    }
    // A static mesh: Bullet's BVH mesh over its own copy of the arrays.
    case ShapeKind::mesh: return std::make_unique<MeshShape>(s);
    case ShapeKind::heightfield: return std::make_unique<HeightfieldShape>(s);
  }
  return nullptr;
}

// A shape's centre of mass in the body frame (a hull's centroid is off its origin).
btVector3 shape_centre(const ShapeSpec& s) {
  return bt(s.local_position) + btMatrix3x3(bt(s.local_orientation)) * bt(s.centroid);
}

// Its inertia per kg about that centre, in its own axes.
btMatrix3x3 own_tensor(const ShapeSpec& s, const ShapeMass& sm) {
  if (s.kind == ShapeKind::hull) {
    const auto& i = s.inertia_per_kg;
    return {bt(i[0][0]), bt(i[0][1]), bt(i[0][2]), bt(i[1][0]), bt(i[1][1]),
            bt(i[1][2]), bt(i[2][0]), bt(i[2][1]), bt(i[2][2])};
  }
  return {bt(sm.inertia_per_kg[0]), 0, 0, 0, bt(sm.inertia_per_kg[1]), 0, 0, 0, bt(sm.inertia_per_kg[2])};
}

bool is_identity(const ShapeSpec& s) {
  return s.local_position == V3{0, 0, 0} && s.local_orientation == Q4{1, 0, 0, 0};
}

class BulletEngine final : public Engine {
 public:
  explicit BulletEngine(const StepConfig& config)
      : dispatcher_(&collision_config_),
        world_(&dispatcher_, &broadphase_, &solver_, &collision_config_) {
    gCalculateCombinedFrictionCallback = combined_friction;
    gCalculateCombinedRestitutionCallback = combined_restitution;
    world_.setGravity(bt(config.gravity));
    world_.getSolverInfo().m_numIterations = config.iterations;
    dt_ = bt(config.dt);
  }

  BulletEngine(const BulletEngine&) = delete;
  BulletEngine& operator=(const BulletEngine&) = delete;

  ~BulletEngine() override {
    // The world refers to the bodies (and they to the shapes): take them out
    // before anything is destroyed, the constraints (which refer to the
    // bodies) first.
    for (Character& c : characters_) {
      world_.removeAction(c.controller.get());
      world_.removeCollisionObject(c.ghost.get());
    }
    if (ghost_callback_) broadphase_.getOverlappingPairCache()->setInternalGhostPairCallback(nullptr);
    for (auto it = constraints_.rbegin(); it != constraints_.rend(); ++it) world_.removeConstraint(it->get());
    for (auto it = bodies_.rbegin(); it != bodies_.rend(); ++it) world_.removeRigidBody(it->rigid.get());
  }

  int add_body(const BodySpec& spec) override {
    // Bullet's rigid body frame must be the centre of mass on principal axes
    // (it stores a diagonal inertia). Compute bitstep's mass properties from
    // the shapes at uniform density, then re-base the shapes onto that frame,
    // principal = (rotation from principal to body axes, centre of mass in the
    // body frame). Specs from scenes are already centred (tools/bench/scene_specs.h),
    // and for one shape at the body origin or a symmetric compound the
    // rotation is identity, so most bodies are created exactly as specified.
    // (The tensor is summed in btScalar: float, like everything Bullet does.)
    double volume = 0;
    btVector3 weighted_centre(0, 0, 0);
    for (const ShapeSpec& s : spec.shapes) {
      const double v = shape_mass(s).volume;
      volume += v;
      weighted_centre += shape_centre(s) * bt(v);
    }
    btTransform principal = btTransform::getIdentity();
    btVector3 inertia(0, 0, 0);
    if (!spec.is_static && volume > 0) {
      principal.setOrigin(weighted_centre / bt(volume));
      // I = sum of R_i diag(I_i) R_i^T + m_i (|d|^2 E - d d^T), d = c_i - c.
      btMatrix3x3 tensor(0, 0, 0, 0, 0, 0, 0, 0, 0);
      for (const ShapeSpec& s : spec.shapes) {
        const ShapeMass sm = shape_mass(s);
        const double m = spec.mass * sm.volume / volume;
        const btMatrix3x3 r(bt(s.local_orientation));
        const btVector3 d = shape_centre(s) - principal.getOrigin();
        btMatrix3x3 shift(-d.x() * d.x(), -d.x() * d.y(), -d.x() * d.z(), -d.y() * d.x(), -d.y() * d.y(),
                          -d.y() * d.z(), -d.z() * d.x(), -d.z() * d.y(), -d.z() * d.z());
        for (int k = 0; k < 3; ++k) shift[k][k] += d.length2();
        tensor = tensor + r * own_tensor(s, sm).scaled(btVector3(bt(m), bt(m), bt(m))) * r.transpose() +
                 shift.scaled(btVector3(bt(m), bt(m), bt(m)));
      }
      btMatrix3x3 rotation;
      tensor.diagonalize(rotation, btScalar(1e-5), 20);  // tensor = rotation diag rotation^T
      principal.setBasis(rotation);
      inertia.setValue(tensor[0][0], tensor[1][1], tensor[2][2]);
    }

    Body body;
    body.principal_rotation = principal.getBasis();
    btCollisionShape* shape = nullptr;
    if (spec.shapes.size() == 1 && is_identity(spec.shapes[0]) && principal == btTransform::getIdentity()) {
      shape = own(make_shape(spec.shapes[0]));
    } else {
      auto compound = std::make_unique<btCompoundShape>();
      for (const ShapeSpec& s : spec.shapes) {
        const btTransform local(bt(s.local_orientation), bt(s.local_position));
        compound->addChildShape(principal.inverse() * local, own(make_shape(s)));
      }
      shape = own(std::move(compound));
    }

    const btScalar mass = spec.is_static ? btScalar(0) : bt(spec.mass);
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, spec.is_static ? btVector3(0, 0, 0) : inertia);
    info.m_startWorldTransform = btTransform(bt(spec.orientation), bt(spec.position)) * principal;
    info.m_friction = bt(spec.dynamic_friction);  // Bullet has one coefficient
    info.m_restitution = bt(spec.restitution);
    info.m_rollingFriction = 0;
    info.m_spinningFriction = 0;
    info.m_linearDamping = 0;
    info.m_angularDamping = 0;
    body.rigid = std::make_unique<btRigidBody>(info);
    if (!spec.is_static) {
      body.rigid->setLinearVelocity(bt(spec.linear_velocity));
      body.rigid->setAngularVelocity(bt(spec.angular_velocity));  // world frame, as the spec
      body.rigid->setActivationState(DISABLE_DEACTIVATION);
    }
    world_.addRigidBody(body.rigid.get());
    bodies_.push_back(std::move(body));
    return static_cast<int>(bodies_.size()) - 1;
  }

  // Pivots and axes in each body's Bullet frame: its centre of mass on its
  // principal axes (add_body), so the world anchor is taken through the
  // inverse of that transform, not the spec's body frame. The joined bodies
  // do not collide (addConstraint's second argument), as in bitstep.
  int add_joint(const JointSpec& spec) override {
    btRigidBody& a = *bodies_[static_cast<size_t>(spec.body_a)].rigid;
    btRigidBody& b = *bodies_[static_cast<size_t>(spec.body_b)].rigid;
    const btTransform& ta = a.getCenterOfMassTransform();
    const btTransform& tb = b.getCenterOfMassTransform();
    const btVector3 anchor = bt(spec.anchor);
    std::unique_ptr<btTypedConstraint> constraint;
    if (spec.kind == JointKind::hinge) {
      const btVector3 axis = bt(spec.axis).normalized();
      auto hinge = std::make_unique<btHingeConstraint>(a, b, ta.inverse() * anchor, tb.inverse() * anchor,
                                                       ta.getBasis().transpose() * axis,
                                                       tb.getBasis().transpose() * axis);
      // Bullet's hinge angle (useReferenceFrameA false) is a's turn relative
      // to b, the opposite sign of the spec's (b's relative to a).
      if (spec.limited) hinge->setLimit(bt(-spec.upper), bt(-spec.lower));
      // Friction as Bullet's examples make it: a motor held at zero speed
      // whose impulse is at most the friction torque over the step.
      if (spec.friction > 0) hinge->enableAngularMotor(true, 0, bt(spec.friction) * dt_);
      constraint = std::move(hinge);
    } else if (spec.kind == JointKind::cone) {
      // btConeTwistConstraint twists about its frames' x axes: each body's
      // frame at the anchor, x along the twist axis. Its twist span is
      // symmetric (the larger of the spec's two limits); it has no
      // friction setting (its motor drives toward a target pose).
      const btVector3 axis = bt(spec.axis).normalized();
      const auto frame_in = [&](const btTransform& t) {
        const btVector3 x = t.getBasis().transpose() * axis;
        btVector3 y, z;
        btPlaneSpace1(x, y, z);
        return btTransform(btMatrix3x3(x.x(), y.x(), z.x(), x.y(), y.y(), z.y(), x.z(), y.z(), z.z()), t.inverse() * anchor);
      };
      auto cone = std::make_unique<btConeTwistConstraint>(a, b, frame_in(ta), frame_in(tb));
      cone->setLimit(bt(spec.swing), bt(spec.swing), bt(std::max(-spec.lower, spec.upper)));
      constraint = std::move(cone);
    } else {
      constraint = std::make_unique<btPoint2PointConstraint>(a, b, ta.inverse() * anchor, tb.inverse() * anchor);
    }
    world_.addConstraint(constraint.get(), true);
    constraints_.push_back(std::move(constraint));
    return static_cast<int>(constraints_.size()) - 1;
  }

  // btKinematicCharacterController, as Bullet's CharacterDemo builds it: a
  // capsule on a btPairCachingGhostObject (the world's pair cache then needs
  // the ghost pair callback), up +y, its gravity the world's (its default is
  // three times Earth's), walking by a displacement per step
  // (setWalkDirection: velocity dt), updated by the world as an action in
  // each stepSimulation.
  int add_character(const CharacterSpec& spec) override {
    if (!ghost_callback_) {
      ghost_callback_ = std::make_unique<btGhostPairCallback>();
      broadphase_.getOverlappingPairCache()->setInternalGhostPairCallback(ghost_callback_.get());
    }
    Character c;
    c.shape = std::make_unique<btCapsuleShape>(bt(spec.radius), bt(2 * spec.half_height));
    c.ghost = std::make_unique<btPairCachingGhostObject>();
    c.ghost->setWorldTransform(btTransform(btQuaternion::getIdentity(), bt(spec.position)));
    c.ghost->setCollisionShape(c.shape.get());
    c.ghost->setCollisionFlags(btCollisionObject::CF_CHARACTER_OBJECT);
    c.controller = std::make_unique<btKinematicCharacterController>(c.ghost.get(), c.shape.get(), bt(spec.step_height),
                                                                    btVector3(0, 1, 0));
    // Its constructor turns the ghost from its own first up (+z) to the
    // given one, which lays a y-axis capsule on its side: stood up again.
    c.ghost->setWorldTransform(btTransform(btQuaternion::getIdentity(), bt(spec.position)));
    c.controller->setGravity(world_.getGravity());
    c.controller->setMaxSlope(bt(spec.max_slope));
    world_.addCollisionObject(c.ghost.get(), btBroadphaseProxy::CharacterFilter,
                              btBroadphaseProxy::StaticFilter | btBroadphaseProxy::DefaultFilter);
    world_.addAction(c.controller.get());
    characters_.push_back(std::move(c));
    return static_cast<int>(characters_.size()) - 1;
  }

  void walk(int character, const V3& velocity) override {
    characters_[static_cast<size_t>(character)].controller->setWalkDirection(bt(velocity) * dt_);
  }

  V3 character_position(int character) const override {
    return dbl(characters_[static_cast<size_t>(character)].ghost->getWorldTransform().getOrigin());
  }

  // maxSubSteps = 0 is Bullet's variable-step mode: exactly one internal step
  // of dt (no fixed-step accumulator, no interpolation).
  void step() override { world_.stepSimulation(dt_, 0); }

  BodyState state(int index) const override {
    const Body& body = bodies_[static_cast<size_t>(index)];
    const btTransform& t = body.rigid->getCenterOfMassTransform();
    // The spec's body axes: Bullet's principal axes turned back.
    btQuaternion q;
    (t.getBasis() * body.principal_rotation.transpose()).getRotation(q);
    return {dbl(t.getOrigin()),
            {dbl(q.w()), dbl(q.x()), dbl(q.y()), dbl(q.z())},
            dbl(body.rigid->getLinearVelocity()),
            dbl(body.rigid->getAngularVelocity())};
  }

  double max_penetration() const override {
    double deepest = 0;
    for (int m = 0; m < dispatcher_.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher_.getManifoldByIndexInternal(m);
      for (int c = 0; c < manifold->getNumContacts(); ++c) {
        deepest = std::fmax(deepest, -dbl(manifold->getContactPoint(c).getDistance()));
      }
    }
    return deepest;
  }

  // FNV-1a 64 over the btScalars Bullet keeps: centre of mass, rotation
  // matrix (Bullet stores a matrix, not a quaternion), linear and angular
  // velocity, body by body in creation order.
  uint64_t state_hash() const override {
    uint64_t hash = 0xcbf29ce484222325ull;
    const auto add = [&hash](btScalar value) {
      unsigned char bytes[sizeof value];
      std::memcpy(bytes, &value, sizeof value);
      for (unsigned char byte : bytes) hash = (hash ^ byte) * 0x100000001b3ull;
    };
    const auto add3 = [&add](const btVector3& v) {
      for (int k = 0; k < 3; ++k) add(v[k]);
    };
    for (const Body& body : bodies_) {
      const btTransform& t = body.rigid->getCenterOfMassTransform();
      add3(t.getOrigin());
      for (int row = 0; row < 3; ++row) add3(t.getBasis()[row]);
      add3(body.rigid->getLinearVelocity());
      add3(body.rigid->getAngularVelocity());
    }
    return hash;
  }

 private:
  struct Body {
    std::unique_ptr<btRigidBody> rigid;
    btMatrix3x3 principal_rotation;  // principal axes -> spec body axes
  };

  struct Character {
    std::unique_ptr<btCapsuleShape> shape;
    std::unique_ptr<btPairCachingGhostObject> ghost;
    std::unique_ptr<btKinematicCharacterController> controller;
  };

  btCollisionShape* own(std::unique_ptr<btCollisionShape> shape) {
    shapes_.push_back(std::move(shape));
    return shapes_.back().get();
  }

  // Declaration order is construction order; destruction runs backwards,
  // bodies and shapes before the world and what it was built from.
  btDefaultCollisionConfiguration collision_config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<Body> bodies_;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
  std::unique_ptr<btGhostPairCallback> ghost_callback_;  // set on the broadphase with the first character
  std::vector<Character> characters_;
  btScalar dt_ = 0;
};

std::unique_ptr<Engine> make_bullet(const StepConfig& config) { return std::make_unique<BulletEngine>(config); }

}  // namespace

std::vector<Variant> peer_variants() {
  std::vector<Variant> variants = {{"bullet", make_bullet}};
  for (const Variant& v : bitstep_variants()) variants.push_back(v);
  return variants;
}

}  // namespace bitstep::bench
