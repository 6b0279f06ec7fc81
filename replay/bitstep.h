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
  BITSTEP_OUT_OF_MEMORY = 5
} bitstep_status;

/* Numbers: exact decimal text ("0.5", "1/60", "-2.5e-3") to Q32.32, rounded
 * once to nearest; and Q32.32 to double, for display only. */
bitstep_status bitstep_fixed_parse(const char* text, bitstep_fixed* out);
double bitstep_fixed_to_double(bitstep_fixed value);

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
/* A body's type: what inputs it takes (impulses and forces a dynamic
 * body, a velocity a dynamic or kinematic one; bitstep_apply_impulse). */
typedef enum { BITSTEP_STATIC = 0, BITSTEP_KINEMATIC = 1, BITSTEP_DYNAMIC = 2 } bitstep_body_type;
bitstep_status bitstep_get_body_type(bitstep_simulation* sim, bitstep_body body, bitstep_body_type* out);
/* Every body slot in use: slots 0 .. bitstep_slot_count() - 1, NOT_FOUND for an empty one. */
uint32_t bitstep_slot_count(const bitstep_simulation* sim);
bitstep_status bitstep_body_in_slot(bitstep_simulation* sim, uint32_t slot, bitstep_body* out);

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
