/* bitstep's C API: a simulation behind an opaque handle, for C and for the
 * languages that bind to C (C#, Godot, Unity). The same facade as the C++
 * one (replay/simulation.h); its numbers are exact Q32.32 (the value times
 * 2^32 in an int64_t) wherever they reach the simulation, so every peer of a
 * lockstep game computes the same bits; floats only for drawing.
 *
 * Every call that can fail returns a bitstep_status; after every failure
 * of a call on a handle, NULL_ARGUMENT included ("get_pose: out is NULL"),
 * bitstep_last_error(sim) holds the one-line message ("scene.json:
 * $.bodies[2].shapes[0].radius: outside 0.01..50 m"). Its pointer is valid
 * until the next call on the same handle, or its destroy: copy the text to
 * keep it. Calls without a handle (a NULL handle, bitstep_fixed_parse,
 * bitstep_state_checksum) report by their status alone; bitstep_create_*
 * write their message into the caller's buffer and set *out to NULL on any
 * failure. Buffers are the caller's: bitstep_save writes into one and says
 * how large it must be. A handle is used by one thread at a time. */
#ifndef BITSTEP_REPLAY_BITSTEP_H
#define BITSTEP_REPLAY_BITSTEP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bitstep_simulation bitstep_simulation;

typedef int64_t bitstep_fixed; /* Q32.32: the value times 2^32 */
typedef struct {
  bitstep_fixed x, y, z;
} bitstep_vec3;
typedef struct {
  bitstep_fixed w, x, y, z;
} bitstep_quat;
typedef struct {
  bitstep_vec3 position;
  bitstep_quat orientation;
} bitstep_pose;
typedef struct {
  float position[3];
  float orientation[4]; /* x, y, z, w */
} bitstep_render_pose;
typedef struct {
  uint32_t index, generation;
} bitstep_body;
typedef struct {
  uint32_t index, generation;
} bitstep_joint;
typedef struct {
  bitstep_body body;
  uint32_t shape;         /* its index in the body's shapes */
  bitstep_fixed fraction; /* of the translation, 0..1 */
  bitstep_vec3 point, normal;
} bitstep_ray_hit;

typedef enum {
  BITSTEP_OK = 0,
  BITSTEP_INVALID = 1,          /* a malformed scene, body, joint, snapshot or number: the message says where */
  BITSTEP_NOT_FOUND = 2,        /* no such body, joint or car; a ray that meets nothing */
  BITSTEP_BUFFER_TOO_SMALL = 3, /* *size says how many bytes are needed */
  BITSTEP_NULL_ARGUMENT = 4,
  BITSTEP_OUT_OF_MEMORY = 5,
  BITSTEP_NOT_READY = 6 /* a session cannot take it now: give it again next frame (replay/bitstep_session.h) */
} bitstep_status;

/* Numbers: exact decimal text ("0.5", "1/60", "-2.5e-3") to Q32.32, rounded
 * once to nearest; and Q32.32 to double, for display only. */
bitstep_status bitstep_fixed_parse(const char* text, bitstep_fixed* out);
double bitstep_fixed_to_double(bitstep_fixed value);
/* Integers to Q32.32 and back, exact or rounded once, to nearest with ties
 * to even (the rule of every rounding in bitstep): from_int is exact;
 * from_ratio is numerator / denominator (INVALID for a zero denominator or
 * a quotient of 2^31 - 1 or more in magnitude); round is the nearest
 * integer. So a binding holding a float x feeds the same bits on every
 * peer by sending an integer (x in millimetres, say) and converting with
 * from_ratio(mm, 1000), never by converting the float. */
bitstep_fixed bitstep_fixed_from_int(int32_t value);
bitstep_status bitstep_fixed_from_ratio(int64_t numerator, int64_t denominator, bitstep_fixed* out);
int64_t bitstep_fixed_round(bitstep_fixed value);

/* A simulation from a scene file or scene JSON text (`name` stands for the
 * file in messages). On failure *out is NULL and the message is written to
 * `error` (cut to error_capacity bytes, NUL-terminated; error may be NULL). */
bitstep_status bitstep_create_from_file(const char* path, bitstep_simulation** out, char* error,
                                        size_t error_capacity);
bitstep_status bitstep_create_from_text(const char* json, size_t length, const char* name, bitstep_simulation** out,
                                        char* error, size_t error_capacity);
void bitstep_destroy(bitstep_simulation* sim);
/* The message of the last call on `sim` that failed ("" before any). */
const char* bitstep_last_error(const bitstep_simulation* sim);

/* Bodies: by scene name; a new one from a body object of the scene format;
 * removal. Joints: a joint object of the scene format, bodies by name. */
bitstep_status bitstep_find_body(bitstep_simulation* sim, const char* name, bitstep_body* out);
bitstep_status bitstep_add_body(bitstep_simulation* sim, const char* body_json, bitstep_body* out);
bitstep_status bitstep_remove_body(bitstep_simulation* sim, bitstep_body body);
bitstep_status bitstep_add_joint(bitstep_simulation* sim, const char* joint_json, bitstep_joint* out);
bitstep_status bitstep_remove_joint(bitstep_simulation* sim, bitstep_joint joint);

/* The same from plain structs (no JSON parsed: a spawn in a rollback's
 * re-simulation costs what the world's creation costs). Start from
 * bitstep_default_*_def (the scene format's defaults) and set what
 * differs. Enumerations are int32_t fields, so a binding's struct is
 * blittable. The world checks a definition as it checks a scene's body
 * (INVALID naming the field: "add_body: shapes[0].radius: outside
 * 0.01..50 m"); orientations are normalised (INVALID when zero). */
typedef enum { BITSTEP_STATIC = 0, BITSTEP_KINEMATIC = 1, BITSTEP_DYNAMIC = 2 } bitstep_body_type;
typedef enum {
  BITSTEP_SHAPE_PLANE = 0, /* static bodies only: local +y is the outward normal, the surface through the origin */
  BITSTEP_SHAPE_BOX = 1,
  BITSTEP_SHAPE_CAPSULE = 2, /* a segment from -half_height to +half_height along local y, swept by radius */
  BITSTEP_SHAPE_SPHERE = 3,
  BITSTEP_SHAPE_HULL = 4,       /* the convex hull of points: 4..1024, within 50 m of its origin, at most 32 corners */
  BITSTEP_SHAPE_MESH = 5,       /* static triangles: made from JSON (bitstep_add_body), read here; not from a struct */
  BITSTEP_SHAPE_HEIGHTFIELD = 6 /* a static grid of heights: from JSON, as a mesh */
} bitstep_shape_type;
typedef struct {
  int32_t type;              /* bitstep_shape_type */
  bitstep_vec3 half_extents; /* box, m */
  bitstep_fixed radius;      /* sphere, capsule, m */
  bitstep_fixed half_height; /* capsule, m */
  bitstep_pose local;        /* in the body's frame */
  /* hull: its points in the shape's frame (m), read while the call runs;
   * bitstep_get_shape gives NULL and the count of its corners
   * (bitstep_get_hull_points reads them) */
  const bitstep_vec3* points;
  uint32_t point_count;
} bitstep_shape;
typedef struct {
  bitstep_fixed static_friction, dynamic_friction; /* >= 0 */
  bitstep_fixed restitution, rolling_resistance;   /* 0..1 */
} bitstep_material;
typedef struct {
  const char* name; /* NULL or "": none; else no other body's */
  int32_t type;     /* bitstep_body_type */
  bitstep_pose pose;
  bitstep_vec3 linear_velocity;  /* m/s */
  bitstep_vec3 angular_velocity; /* rad/s, world frame */
  bitstep_fixed density;         /* kg/m^3, unless mass > 0 (kg): then scaled to give it */
  bitstep_fixed mass;
  bitstep_material material;
  bitstep_fixed linear_damping, angular_damping; /* 1/s, >= 0 */
  uint32_t layers, collides_with;                /* collision filter bits */
  int32_t asleep;                                /* start asleep (dynamic, at rest) */
  int32_t sensor;                                /* reports overlaps, pushes nothing */
  const bitstep_shape* shapes;
  uint32_t shape_count; /* 1..256 */
} bitstep_body_def;
typedef enum {
  BITSTEP_JOINT_POINT = 0,
  BITSTEP_JOINT_MAX_DISTANCE = 1, /* a rope */
  BITSTEP_JOINT_HINGE = 2,
  BITSTEP_JOINT_CONE = 3, /* a ragdoll's shoulder or hip */
  BITSTEP_JOINT_SLIDER = 4
} bitstep_joint_type;
/* In the world frame at creation (the fields as the scene format's). */
typedef struct {
  int32_t type; /* bitstep_joint_type */
  bitstep_body body_a, body_b;
  bitstep_vec3 anchor_a; /* the joined point (a rope's end on a) */
  bitstep_vec3 anchor_b; /* a rope's end on b */
  bitstep_fixed length;  /* a rope's; 0: the anchors' distance now */
  bitstep_vec3 axis;     /* hinge axis, cone twist axis, slider axis */
  int32_t limited;
  bitstep_fixed lower_angle, upper_angle, swing_angle; /* rad */
  bitstep_fixed lower_translation, upper_translation;  /* m */
  bitstep_fixed motor_speed, motor_max;
  bitstep_fixed break_impulse;                       /* N s; 0: never breaks */
  bitstep_fixed friction_torque;                     /* N m (a slider's N) */
  uint16_t velocity_iterations, position_iterations; /* 0: the world's */
} bitstep_joint_def;
bitstep_body_def bitstep_default_body_def(void);
bitstep_joint_def bitstep_default_joint_def(void);
bitstep_status bitstep_create_body(bitstep_simulation* sim, const bitstep_body_def* def, bitstep_body* out);
bitstep_status bitstep_create_joint(bitstep_simulation* sim, const bitstep_joint_def* def, bitstep_joint* out);
/* A body's type: what inputs it takes (impulses and forces a dynamic
 * body, a velocity a dynamic or kinematic one; bitstep_apply_impulse). */
bitstep_status bitstep_get_body_type(bitstep_simulation* sim, bitstep_body body, bitstep_body_type* out);
/* Every body slot in use: slots 0 .. bitstep_slot_count() - 1, NOT_FOUND for an empty one. */
uint32_t bitstep_slot_count(const bitstep_simulation* sim);
bitstep_status bitstep_body_in_slot(bitstep_simulation* sim, uint32_t slot, bitstep_body* out);
/* A body's velocities, of its centre of mass (as Box2D and Jolt report
 * them; what set_velocity sets); whether it sleeps (0 or 1; 0 for static
 * and kinematic bodies); its name (as bitstep_save: *size the bytes needed
 * with the NUL, BUFFER_TOO_SMALL when capacity is less; "" for none); its
 * shapes, their local poses in the body's frame as it was defined. */
bitstep_status bitstep_get_velocity(bitstep_simulation* sim, bitstep_body body, bitstep_vec3* linear,
                                    bitstep_vec3* angular);
bitstep_status bitstep_is_asleep(bitstep_simulation* sim, bitstep_body body, int32_t* out);
bitstep_status bitstep_get_body_name(bitstep_simulation* sim, bitstep_body body, char* buffer, size_t capacity,
                                     size_t* size);
bitstep_status bitstep_get_shape_count(bitstep_simulation* sim, bitstep_body body, uint32_t* out);
bitstep_status bitstep_get_shape(bitstep_simulation* sim, bitstep_body body, uint32_t index, bitstep_shape* out);
/* A hull shape's corners (the shape's frame, in the builder's order):
 * *count of them; BUFFER_TOO_SMALL, nothing written, when capacity is less
 * (a NULL buffer of capacity 0 asks); INVALID for a shape of another type. */
bitstep_status bitstep_get_hull_points(bitstep_simulation* sim, bitstep_body body, uint32_t index, bitstep_vec3* out,
                                       size_t capacity, size_t* count);

/* Inputs for the next step, bounded as a replay's inputs are (so a match
 * played through this API can be recorded and replayed):
 *   apply_impulse  impulse  each component within +-1000000 N s
 *   apply_force    force    each component within +-1000000 N
 *   both           world_point  each component within +-16000 m
 *   set_velocity   linear   each component and the length within 500 m/s
 *                  angular  each component and the length within 100 rad/s
 *   drive          throttle -1..1, brake 0..1, steer -1..1
 * A value past its bound returns BITSTEP_INVALID and changes nothing (the
 * hash stays); the message names the call, the argument and the bound
 * ("set_velocity: linear.y: outside +-500 m/s", "set_velocity: angular:
 * faster than 100 rad/s"). So does an input the body cannot take: an
 * impulse or a force on a static or kinematic body, a velocity on a static
 * one ("apply_impulse: the body is static: impulses move dynamic bodies"). A handle no body has (removed, stale, never
 * made) returns BITSTEP_NOT_FOUND, checked before the values. Numbers are
 * Q32.32 integers: a binding converting from floating point must refuse
 * NaN and infinities itself (C leaves their conversion to an integer
 * undefined). */
bitstep_status bitstep_apply_impulse(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 impulse,
                                     bitstep_vec3 world_point);
bitstep_status bitstep_apply_force(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 force,
                                   bitstep_vec3 world_point);
bitstep_status bitstep_set_velocity(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 linear,
                                    bitstep_vec3 angular);
bitstep_status bitstep_wake(bitstep_simulation* sim, bitstep_body body);
bitstep_status bitstep_drive(bitstep_simulation* sim, const char* car, bitstep_fixed throttle, bitstep_fixed brake,
                             bitstep_fixed steer);

/* A scene character's desired level velocity (x and z within +-100 m/s;
 * its y is ignored) and jump (non-zero: jump when on walkable ground, held
 * until cleared), from the next step on, as a replay's "move" input. */
bitstep_status bitstep_move_character(bitstep_simulation* sim, const char* character, bitstep_vec3 velocity,
                                      int32_t jump);

/* A new character from one character object of the scene format (JSON:
 * "name", a name no live character has, "position" and the optional
 * fields of a scene's "characters"), standing where it is created; the
 * JSON refusal names the field. remove: NOT_FOUND for a name no live
 * character has. As a replay's add_character and remove_character inputs. */
bitstep_status bitstep_add_character(bitstep_simulation* sim, const char* character_json);
bitstep_status bitstep_remove_character(bitstep_simulation* sim, const char* character);

/* Where a character is and what it stands on (core/character.h). */
typedef enum { BITSTEP_ON_GROUND = 0, BITSTEP_ON_STEEP_SLOPE = 1, BITSTEP_IN_AIR = 2 } bitstep_ground_state;
typedef struct {
  bitstep_vec3 position;    /* the capsule's centre */
  bitstep_vec3 velocity;    /* its own (a platform it rides adds its motion) */
  bitstep_vec3 facing;      /* unit, level */
  int32_t ground;           /* a bitstep_ground_state */
  bitstep_body ground_body; /* what it stands on; {UINT32_MAX, 0} in the air */
  bitstep_vec3 ground_normal;
} bitstep_character_state;
/* NOT_FOUND for a name no live character has. */
bitstep_status bitstep_get_character(bitstep_simulation* sim, const char* character, bitstep_character_state* out);

bitstep_status bitstep_step(bitstep_simulation* sim);
uint64_t bitstep_tick(const bitstep_simulation* sim);
/* The state hash of the replays' chains. */
uint64_t bitstep_hash(const bitstep_simulation* sim);

/* A body's frame as its scene defined it (not its centre of mass), exact,
 * or as floats for drawing; and a pose between two steps' (alpha 0..1). */
bitstep_status bitstep_get_pose(bitstep_simulation* sim, bitstep_body body, bitstep_pose* out);
bitstep_status bitstep_get_render_pose(bitstep_simulation* sim, bitstep_body body, bitstep_render_pose* out);
void bitstep_interpolate(const bitstep_render_pose* from, const bitstep_render_pose* to, float alpha,
                         bitstep_render_pose* out);
/* Every live body's pose at once, in slot order (a frame's drawing in one
 * call): *count the live bodies; BUFFER_TOO_SMALL, nothing written, when
 * capacity is less (a NULL buffer of capacity 0 asks). */
typedef struct {
  bitstep_body body;
  bitstep_pose pose;
} bitstep_body_pose;
typedef struct {
  bitstep_body body;
  bitstep_render_pose pose;
} bitstep_body_render_pose;
bitstep_status bitstep_get_poses(bitstep_simulation* sim, bitstep_body_pose* out, size_t capacity, size_t* count);
bitstep_status bitstep_get_render_poses(bitstep_simulation* sim, bitstep_body_render_pose* out, size_t capacity,
                                        size_t* count);

/* The last step's events, in this order: joints that broke (always
 * listed: their handles died), then, once bitstep_set_events(sim, 1), the
 * shapes that began or ended touching, contacts then sensors, then bodies
 * that left the world past +-524288 m (always listed). Sizes as
 * bitstep_get_poses. A body's handle in an event is the one the game
 * holds, also for a body that has just gone. Events are off by default:
 * they cost two passes over the step's contacts. */
typedef enum {
  BITSTEP_CONTACT_BEGIN = 0, /* body_a's shape_a began touching body_b's shape_b */
  BITSTEP_CONTACT_END = 1,
  BITSTEP_SENSOR_BEGIN = 2, /* a shape began overlapping a sensor's shape */
  BITSTEP_SENSOR_END = 3,
  BITSTEP_LEFT_WORLD = 4,  /* body_a (= body_b) was removed */
  BITSTEP_JOINT_BROKEN = 5 /* `joint`, between body_a and body_b, passed its break_impulse and was removed */
} bitstep_event_type;
typedef struct {
  int32_t type; /* bitstep_event_type */
  bitstep_body body_a, body_b;
  uint32_t shape_a, shape_b;
  bitstep_joint joint;
} bitstep_event;
bitstep_status bitstep_set_events(bitstep_simulation* sim, int32_t on);
bitstep_status bitstep_get_events(bitstep_simulation* sim, bitstep_event* out, size_t capacity, size_t* count);

/* The state as a snapshot image into the caller's buffer (BUFFER_TOO_SMALL
 * with *size the bytes needed; a NULL buffer of capacity 0 asks), and a
 * restore from one (INVALID, nothing changed, when the image is not one). */
bitstep_status bitstep_save(bitstep_simulation* sim, uint8_t* buffer, size_t capacity, size_t* size);
bitstep_status bitstep_load(bitstep_simulation* sim, const uint8_t* image, size_t size);
/* A rollback game's save and load: the step's state alone (no shapes or
 * masses), into the caller's buffer without allocating once every body was
 * seen, restored in place; only into the simulation that saved it, and not
 * across a bitstep_load. Sizes as bitstep_save; INVALID, nothing changed,
 * when the image is refused (it is read whole before it replaces anything). */
bitstep_status bitstep_save_state(bitstep_simulation* sim, uint8_t* buffer, size_t capacity, size_t* size);
bitstep_status bitstep_load_state(bitstep_simulation* sim, const uint8_t* image, size_t size);
/* The checksum a saved state carries (no second pass over the state): what
 * peers compare. It names nothing of one simulation object (no body serial,
 * no save number), so peers in the same state have the same one however
 * their simulations were built; a body's shapes and masses are not in it
 * (bitstep_hash covers them). INVALID when the image is not a state of this
 * version (not verified: bitstep_load_state does). bitstep_checksum: the
 * same of the simulation now. */
bitstep_status bitstep_state_checksum(const uint8_t* image, size_t size, uint64_t* checksum);
uint64_t bitstep_checksum(const bitstep_simulation* sim);

/* The first shape a ray from origin along translation meets (NOT_FOUND: none).
 * A query changes nothing, so it takes any numbers: a zero translation, an
 * origin beyond 65536 m or a translation longer than 131072 m meets nothing. */
bitstep_status bitstep_cast_ray(bitstep_simulation* sim, bitstep_vec3 origin, bitstep_vec3 translation,
                                bitstep_ray_hit* out);

#ifdef __cplusplus
}
#endif

#endif
