// JigLib's raycast car: a chassis body on wheels that are rays,
// not bodies. "The car just uses ray casts for the suspension (you can set
// it up to use multiple rays per wheel). Drive forces are applied at each
// wheel to both the chassis, the wheel, and the object that it touches."
// Each step, before the solve, every wheel casts its rays (core/query.h)
// down the chassis's -y from its attachment, and where it touches, the
// wheel is three rows of the contact solve (core/tyre_rows.h): the
// suspension, a spring and damper along the ground's normal as a soft
// unilateral row (the spring integrated implicitly: any stiffness is
// stable at any step), and the tyre in the ground's plane (drive, brake,
// and the side grip that stops sliding sideways) as friction rows within
// the friction circle of the suspension row's impulse. Each impulse goes
// to the chassis and, opposite, to the body under the wheel.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/aabb.h"
#include "core/body.h"
#include "core/error.h"

namespace bitstep {

struct WheelDef {
  Vec3 attachment;  // m, the suspension's top in the chassis frame (about its centre of mass)
  bool driven = false;
  bool steered = false;
};

// Defaults: a 1,000-1,500 kg road car.
struct CarDef {
  BodyId chassis;
  std::vector<WheelDef> wheels;            // 1..8; the car faces the chassis's +z, its up is +y
  Fixed wheel_radius = 0.35_fx;            // m
  Fixed rest_length = 0.3_fx;              // m, attachment to wheel centre, unloaded
  Fixed stiffness = 40000.0_fx;            // N/m per wheel
  Fixed damping = 3000.0_fx;               // N s/m per wheel
  Fixed grip = 1.0_fx;                     // the tyre's friction, mixed with the ground's (geometric mean)
  Fixed drive_force = 2000.0_fx;           // N per driven wheel at full throttle
  Fixed brake_force = 10000.0_fx;          // N per wheel at full brake (the grip bounds it)
  Fixed max_steer = 0.5_fx;                // rad, the steered wheels' turn at full steer
  int rays_per_wheel = 1;                  // 1..8, spread along the wheel's forward direction
};

// The driver's controls, kept until changed (replay inputs set them).
struct CarControls {
  Fixed throttle;  // -1..1 (negative: reverse)
  Fixed brake;     // 0..1
  Fixed steer;     // -1..1 (positive: left, turning about +y)
  friend bool operator==(const CarControls&, const CarControls&) = default;
};

// What a wheel found at the start of the last step, and the force its tyre
// gave (not state: found again every step).
struct WheelState {
  bool on_ground = false;
  Fixed compression;        // m, of the suspension (0 at rest_length)
  Fixed suspension_force;   // N, along normal, on the chassis: the solve's suspension impulse / dt
  Vec3 point, normal;       // where the wheel touches, and the ground's normal
  Vec3 tyre_force;          // N, in the ground's plane, on the chassis: the solve's tyre impulse / dt
  uint32_t ground = UINT32_MAX;  // the touched body's slot
};

// A wheel's impulses accumulated in the last step's solve, which start the
// next one's (warm starting, as contacts'): N s on the chassis, of the
// suspension along the ground's normal, and of the tyre along the wheel's
// heading and across it; zero for a wheel off the ground.
struct TyreImpulse {
  Fixed suspension, forward, side;
  friend bool operator==(const TyreImpulse&, const TyreImpulse&) = default;
};

struct Car {
  bool alive = false;
  CarDef def;
  CarControls controls;
  std::vector<TyreImpulse> tyre_impulses;  // per wheel (state: hashed, saved)
  std::vector<WheelState> wheels;
};

struct CarId {
  uint32_t index = UINT32_MAX;
  bool valid() const { return index != UINT32_MAX; }
};

// A car definition's checks: refused with its field and why ("wheels",
// "1..8"), or fine.
Result<void> check_car(const CarDef& def, const std::vector<Body>& bodies);

class WorldQuery;
struct TyreContact;

// Where the live cars' wheel rays can reach: every chassis's bounds grown
// by its farthest attachment plus the suspension and the wheel (a
// WorldQuery over this region answers their rays exactly).
Aabb car_region(const std::vector<Car>& cars, const std::vector<Body>& bodies);

// Every live car's grounded wheels, for the solve (core/tyre_rows.h): where
// each touches, its suspension row's coefficients for the step `dt`, and
// its tyre's bounds and grip. `query` is a snapshot of the world at the
// step's start. Sleeping bodies a car pushes, and a sleeping chassis whose
// driver opens the throttle, are listed in `to_wake`.
void drive_cars(const WorldQuery& query, Fixed dt, std::vector<Body>& bodies, std::vector<Car>& cars,
                std::vector<TyreContact>& tyres, std::vector<uint32_t>& to_wake);
// The wheels' impulses the solve settled on, kept to warm-start the next
// step, and their forces (suspension and tyre), into the cars' wheel states.
void record_tyre_forces(const std::vector<TyreContact>& tyres, Fixed dt, std::vector<Car>& cars);

}  // namespace bitstep
