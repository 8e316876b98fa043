/* soadyn's C API: load a model file, simulate it, drive it and read it from C or any language with a C
 * foreign-function interface (the FMU is built on it). Plain C, stable ABI: opaque handles, int status codes,
 * caller-owned arrays. SOADYN_C_API_VERSION rises when a function is added; nothing is removed or changed
 * within a major version.
 *
 * Inputs follow hybrid_dynamics: u of a regular DOF is its torque (N m) or force (N); u of a DOF that follows
 * its input (soadyn_sim_prescribe, or a DOF the model marks prescribed) is its acceleration (rad/s^2, m/s^2),
 * or its velocity or position (soadyn_sim_set_input_kind), held from the call until changed. Units are SI; q and v as in the Python API (quaternions x y z w, body-frame
 * velocities of free, spherical and planar joints).
 *
 * Real time: after soadyn_sim_create, every call on a simulator (inputs, steps, mode switches, reads, saving
 * and loading states) allocates nothing, takes no lock, does no I/O and throws nothing; a failure returns
 * SOADYN_ERROR and leaves the simulator as it was, with the reason in soadyn_last_error() (the message alone is
 * built then). A simulator is not safe to use from two threads at once; different simulators are.
 */
#ifndef SOADYN_C_API_H
#define SOADYN_C_API_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SOADYN_C_API_VERSION 2
#define SOADYN_OK 0
#define SOADYN_ERROR 1

#if defined(_WIN32)
#define SOADYN_C_EXPORT __declspec(dllexport)
#else
#define SOADYN_C_EXPORT __attribute__((visibility("default")))
#endif

typedef struct soadyn_model soadyn_model;
typedef struct soadyn_sim soadyn_sim;

/* The version this library implements (SOADYN_C_API_VERSION when it was built). */
SOADYN_C_EXPORT int soadyn_c_api_version(void);
/* The last error of this thread, as a sentence naming the item at fault ("" when none). */
SOADYN_C_EXPORT const char* soadyn_last_error(void);

/* Models: a soadyn model file (soadyn.save_model) by path, or its text. NULL on failure. */
SOADYN_C_EXPORT soadyn_model* soadyn_model_load(const char* path);
SOADYN_C_EXPORT soadyn_model* soadyn_model_from_json(const char* text);
SOADYN_C_EXPORT void soadyn_model_free(soadyn_model* model);
SOADYN_C_EXPORT int soadyn_model_nq(const soadyn_model* model);
SOADYN_C_EXPORT int soadyn_model_nv(const soadyn_model* model);
/* Names (valid while the model lives; NULL out of range) and the DOF of a name (-1 if none). */
SOADYN_C_EXPORT const char* soadyn_model_dof_name(const soadyn_model* model, int dof);
SOADYN_C_EXPORT const char* soadyn_model_coordinate_name(const soadyn_model* model, int coordinate);
SOADYN_C_EXPORT int soadyn_model_dof_index(const soadyn_model* model, const char* name);
SOADYN_C_EXPORT int soadyn_model_is_prescribed(const soadyn_model* model, int dof);

/* A simulator of a copy of `model` stepping dt seconds with integrator "rk4", "euler" or "dopri5"; it starts
 * at the neutral configuration, at rest, at t = 0, every DOF the model marks prescribed following its input
 * (acceleration 0). NULL on failure. */
SOADYN_C_EXPORT soadyn_sim* soadyn_sim_create(const soadyn_model* model, double dt, const char* integrator);
SOADYN_C_EXPORT void soadyn_sim_free(soadyn_sim* sim);

/* u of one DOF (by velocity index or name); applied from the next step on. */
SOADYN_C_EXPORT int soadyn_sim_set_input(soadyn_sim* sim, int dof, double u);
SOADYN_C_EXPORT int soadyn_sim_set_input_by_name(soadyn_sim* sim, const char* dof, double u);
/* Mode switches, now: lock (stop the DOF with the impulse that brings it to rest, then hold it), release
 * (regular: torque input), prescribe (follow its input acceleration from where it is, without an impulse). */
SOADYN_C_EXPORT int soadyn_sim_lock(soadyn_sim* sim, int dof);
SOADYN_C_EXPORT int soadyn_sim_release(soadyn_sim* sim, int dof);
SOADYN_C_EXPORT int soadyn_sim_prescribe(soadyn_sim* sim, int dof);

/* Setup (since version 2; allocates): what u of a DOF that follows its input gives, "acceleration" (the
 * default), "velocity" (reached at the end of the next soadyn_sim_step call, at a constant acceleration) or
 * "position" (reached at the end of the next soadyn_sim_step call along a cubic, velocity continuous; the
 * C++ header soadyn/embed/plant.hpp gives the motions). */
SOADYN_C_EXPORT int soadyn_sim_set_input_kind(soadyn_sim* sim, int dof, const char* kind);
/* Setup (since version 2; allocates): a wrench input on a body or named frame; returns its index (>= 0), or
 * -1 on failure. soadyn_sim_set_wrench sets it: [tx ty tz fx fy fz] in the frame's own axes about its
 * origin (N m, N), applied from the next step on until changed. */
SOADYN_C_EXPORT int soadyn_sim_add_wrench_input(soadyn_sim* sim, const char* frame);
SOADYN_C_EXPORT int soadyn_sim_set_wrench(soadyn_sim* sim, int wrench, const double values[6]);

/* `steps` steps of dt; on failure the state is that after the last step done. */
SOADYN_C_EXPORT int soadyn_sim_step(soadyn_sim* sim, int steps);
SOADYN_C_EXPORT double soadyn_sim_time(const soadyn_sim* sim);

/* Reads into caller arrays of exactly nq (q) or nv (v, qdd, tau) entries. qdd and tau are the accelerations
 * and generalized forces at the present state and inputs (every DOF's: the drive torque of a driven one). */
SOADYN_C_EXPORT int soadyn_sim_get_q(const soadyn_sim* sim, double* q, int nq);
SOADYN_C_EXPORT int soadyn_sim_get_v(const soadyn_sim* sim, double* v, int nv);
SOADYN_C_EXPORT int soadyn_sim_get_qdd_tau(soadyn_sim* sim, double* qdd, double* tau, int nv);

/* Sets q (nq), v (nv) and the time t; refused (naming the entry) when not finite or a quaternion is off unit
 * norm. Not real time: it allocates the error message only. */
SOADYN_C_EXPORT int soadyn_sim_set_state(soadyn_sim* sim, const double* q, int nq, const double* v, int nv, double t);

/* The whole simulator state (time, q, v, inputs, each DOF's mode and input motion) as bytes: a buffer of
 * soadyn_sim_state_size bytes, loaded back by the same model's simulators (rollback). A buffer of another
 * size, model or version, or with values out of range, is refused. */
SOADYN_C_EXPORT size_t soadyn_sim_state_size(const soadyn_sim* sim);
SOADYN_C_EXPORT int soadyn_sim_save_state(const soadyn_sim* sim, void* buffer, size_t size);
SOADYN_C_EXPORT int soadyn_sim_load_state(soadyn_sim* sim, const void* buffer, size_t size);

#ifdef __cplusplus
}
#endif

#endif /* SOADYN_C_API_H */
