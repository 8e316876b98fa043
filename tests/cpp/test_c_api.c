/* The C API from C (soadyn/embed/c_api.h): a two-link pendulum loaded from its model file's text, stepped,
 * driven (a torque, a lock, a prescribed acceleration, velocity and position, a wrench), rolled back through a saved state, and refused with a
 * message where the arguments are wrong. Compiled as C99; prints one line per check and a PASS line that
 * tests/cpp/check_summary.py requires. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "soadyn/embed/c_api.h"

/* soadyn.save_model(soadyn.scenes.pendulum_chain(2)): two 0.5 m, 1 kg rods about parallel x axes. */
static const char* kPendulum =
    "{\"format\":\"soadyn-model\",\"version\":1,\"gravity\":[0.0,0.0,-9.81],\"bodies\":[{\"name\":\"link_1\",\"parent\":\""
    "world\",\"joint\":{\"type\":\"revolute\",\"name\":\"link_1\",\"axis\":[1.0,0.0,0.0]},\"placement\":{\"rotation\":[[1."
    "0,0.0,0.0],[0.0,1.0,0.0],[0.0,0.0,1.0]],\"translation\":[0.0,0.0,0.0]},\"mass\":1.0,\"com\":[0.0,0.0,-0.25"
    "],\"inertia\":[[0.020833333333333332,0.0,0.0],[0.0,0.020833333333333332,0.0],[0.0,0.0,0.001]],\"spatial"
    "_inertia\":[[0.08333333333333333,0.0,0.0,0.0,0.25,0.0],[0.0,0.08333333333333333,0.0,-0.25,0.0,-0.0],["
    "0.0,0.0,0.0010000000000000009,-0.0,0.0,0.0],[-0.0,-0.25,-0.0,1.0,0.0,0.0],[0.25,-0.0,0.0,0.0,1.0,0.0"
    "],[0.0,-0.0,-0.0,0.0,0.0,1.0]]},{\"name\":\"link_2\",\"parent\":\"link_1\",\"joint\":{\"type\":\"revolute\",\"name\""
    ":\"link_2\",\"axis\":[1.0,0.0,0.0]},\"placement\":{\"rotation\":[[1.0,0.0,0.0],[0.0,1.0,0.0],[0.0,0.0,1.0]],"
    "\"translation\":[0.0,0.0,-0.5]},\"mass\":1.0,\"com\":[0.0,0.0,-0.25],\"inertia\":[[0.020833333333333332,0.0,"
    "0.0],[0.0,0.020833333333333332,0.0],[0.0,0.0,0.001]],\"spatial_inertia\":[[0.08333333333333333,0.0,0.0"
    ",0.0,0.25,0.0],[0.0,0.08333333333333333,0.0,-0.25,0.0,-0.0],[0.0,0.0,0.0010000000000000009,-0.0,0.0,"
    "0.0],[-0.0,-0.25,-0.0,1.0,0.0,0.0],[0.25,-0.0,0.0,0.0,1.0,0.0],[0.0,-0.0,-0.0,0.0,0.0,1.0]]}],\"frame"
    "s\":[],\"loops\":[],\"joint_springs\":[],\"point_springs\":[],\"prescribed\":[],\"armature\":{},\"description\":{"
    "}}";

static int failures = 0;

static void check(int ok, const char* what) {
  printf("%s: %s\n", ok ? "ok" : "FAILED", what);
  if (!ok) ++failures;
}

int main(void) {
  check(soadyn_c_api_version() == SOADYN_C_API_VERSION, "the library's version is the header's");
  soadyn_model* model = soadyn_model_from_json(kPendulum);
  check(model != NULL, "the model loads");
  if (!model) return 1;
  const int nq = soadyn_model_nq(model), nv = soadyn_model_nv(model);
  check(nq == 2 && nv == 2 && soadyn_model_dof_index(model, "link_2") == 1 &&
            strcmp(soadyn_model_dof_name(model, 0), "link_1") == 0,
        "sizes and names");

  soadyn_sim* sim = soadyn_sim_create(model, 1e-3, "rk4");
  check(sim != NULL, "a simulator");
  const double q0[2] = {0.5, 0.0}, v0[2] = {0.0, 0.0};
  check(soadyn_sim_set_state(sim, q0, 2, v0, 2, 0.0) == SOADYN_OK, "set_state");

  /* Rollback: the same 500 steps from a saved state give the same state bit for bit. */
  const size_t size = soadyn_sim_state_size(sim);
  unsigned char* saved = malloc(size);
  check(soadyn_sim_save_state(sim, saved, size) == SOADYN_OK, "save_state");
  double q_first[2], q_again[2], v[2];
  soadyn_sim_set_input_by_name(sim, "link_2", 0.3);
  check(soadyn_sim_step(sim, 500) == SOADYN_OK, "500 steps");
  soadyn_sim_get_q(sim, q_first, 2);
  check(soadyn_sim_load_state(sim, saved, size) == SOADYN_OK, "load_state");
  soadyn_sim_set_input_by_name(sim, "link_2", 0.3);
  soadyn_sim_step(sim, 500);
  soadyn_sim_get_q(sim, q_again, 2);
  check(memcmp(q_first, q_again, sizeof q_first) == 0 && fabs(soadyn_sim_time(sim) - 0.5) < 1e-12,
        "the rolled-back run repeats bit for bit");

  /* A lock stops the DOF and holds it; a prescribed acceleration moves it as a closed form says. */
  check(soadyn_sim_lock(sim, 0) == SOADYN_OK, "lock link_1");
  soadyn_sim_step(sim, 100);
  soadyn_sim_get_v(sim, v, 2);
  check(v[0] == 0.0, "a locked DOF stays at rest");
  double q_start[2], q_end[2];
  soadyn_sim_get_q(sim, q_start, 2);
  check(soadyn_sim_prescribe(sim, 0) == SOADYN_OK, "prescribe link_1");
  soadyn_sim_set_input(sim, 0, 2.0); /* rad/s^2 */
  soadyn_sim_step(sim, 250);         /* 0.25 s: q = q_start + 2 * 0.25^2 / 2 */
  soadyn_sim_get_q(sim, q_end, 2);
  check(fabs(q_end[0] - (q_start[0] + 0.0625)) < 1e-12, "a prescribed DOF follows its input acceleration");
  double qdd[2], tau[2];
  check(soadyn_sim_get_qdd_tau(sim, qdd, tau, 2) == SOADYN_OK && qdd[0] == 2.0 && isfinite(tau[0]),
        "qdd and tau at the present state (the drive torque of the prescribed DOF)");

  /* Velocity and position inputs reach their values at the end of the soadyn_sim_step call. */
  check(soadyn_sim_set_input_kind(sim, 0, "velocity") == SOADYN_OK, "link_1 follows a velocity input");
  soadyn_sim_set_input(sim, 0, -0.7);
  soadyn_sim_step(sim, 40);
  soadyn_sim_get_v(sim, v, 2);
  check(fabs(v[0] + 0.7) < 1e-12, "a velocity input is reached at the end of the call");
  check(soadyn_sim_set_input_kind(sim, 0, "position") == SOADYN_OK, "link_1 follows a position input");
  soadyn_sim_set_input(sim, 0, 0.25);
  soadyn_sim_step(sim, 30);
  soadyn_sim_get_q(sim, q_end, 2);
  check(fabs(q_end[0] - 0.25) < 1e-12, "a position input is reached at the end of the call");
  check(soadyn_sim_set_input_kind(sim, 0, "jerk") == SOADYN_ERROR && strstr(soadyn_last_error(), "jerk") != NULL,
        "an unknown input kind is named");
  check(soadyn_sim_release(sim, 0) == SOADYN_OK, "release link_1");

  /* A pure torque about x on link_2 is the generalized force (tau, tau) (hinges about parallel x axes). */
  soadyn_sim* through_wrench = soadyn_sim_create(model, 1e-3, "rk4");
  soadyn_sim* through_torques = soadyn_sim_create(model, 1e-3, "rk4");
  const int wrench = soadyn_sim_add_wrench_input(through_wrench, "link_2");
  const double torque_x[6] = {0.8, 0.0, 0.0, 0.0, 0.0, 0.0};
  check(wrench == 0 && soadyn_sim_set_wrench(through_wrench, wrench, torque_x) == SOADYN_OK, "a wrench input");
  soadyn_sim_set_state(through_wrench, q0, 2, v0, 2, 0.0);
  soadyn_sim_set_state(through_torques, q0, 2, v0, 2, 0.0);
  soadyn_sim_set_input(through_torques, 0, 0.8);
  soadyn_sim_set_input(through_torques, 1, 0.8);
  soadyn_sim_step(through_wrench, 300);
  soadyn_sim_step(through_torques, 300);
  double q_wrench[2], q_torques[2];
  soadyn_sim_get_q(through_wrench, q_wrench, 2);
  soadyn_sim_get_q(through_torques, q_torques, 2);
  check(fabs(q_wrench[0] - q_torques[0]) < 1e-12 && fabs(q_wrench[1] - q_torques[1]) < 1e-12 &&
            fabs(q_wrench[0] - q0[0]) > 1e-3,
        "a torque wrench equals the joint torques it implies");
  check(soadyn_sim_add_wrench_input(through_wrench, "nowhere") == -1 && strstr(soadyn_last_error(), "nowhere") != NULL,
        "an unknown wrench frame is named");
  check(soadyn_sim_set_wrench(through_wrench, 3, torque_x) == SOADYN_ERROR &&
            strstr(soadyn_last_error(), "wrench input 3") != NULL,
        "a wrench input out of range is named");
  const double bad[6] = {0.0, NAN, 0.0, 0.0, 0.0, 0.0};
  soadyn_sim_set_wrench(through_wrench, wrench, bad);
  check(soadyn_sim_step(through_wrench, 1) == SOADYN_ERROR && strstr(soadyn_last_error(), "wrench input 0") != NULL,
        "a NaN wrench fails the step, naming the input");
  soadyn_sim_free(through_wrench);
  soadyn_sim_free(through_torques);

  /* Errors: SOADYN_ERROR with the reason, nothing changed. */
  check(soadyn_sim_set_input(sim, 7, 1.0) == SOADYN_ERROR && strstr(soadyn_last_error(), "DOF index 7") != NULL,
        "a DOF out of range is named");
  check(soadyn_sim_get_q(sim, q_end, 3) == SOADYN_ERROR && strstr(soadyn_last_error(), "3 entries") != NULL,
        "an array of the wrong size is named");
  saved[0] = 'X';
  check(soadyn_sim_load_state(sim, saved, size) == SOADYN_ERROR && strstr(soadyn_last_error(), "magic") != NULL,
        "a corrupted state is refused");
  check(soadyn_sim_load_state(sim, saved, size - 1) == SOADYN_ERROR, "a state of the wrong size is refused");
  soadyn_sim_set_input(sim, 1, NAN);
  check(soadyn_sim_step(sim, 1) == SOADYN_ERROR && strstr(soadyn_last_error(), "link_2") != NULL,
        "a NaN torque fails the step, naming the DOF");
  check(soadyn_sim_create(model, -1.0, "rk4") == NULL && strstr(soadyn_last_error(), "dt") != NULL,
        "a negative dt is refused");
  check(soadyn_sim_create(model, 1e-3, "magic") == NULL && strstr(soadyn_last_error(), "magic") != NULL,
        "an unknown integrator is named");
  check(soadyn_model_load("/nonexistent/model.json") == NULL && strlen(soadyn_last_error()) > 0,
        "a missing model file is refused with a message");
  check(soadyn_model_from_json("{\"format\": \"soadyn-model\"}") == NULL && strlen(soadyn_last_error()) > 0,
        "a malformed model is refused with a message");

  free(saved);
  soadyn_sim_free(sim);
  soadyn_model_free(model);
  if (failures) return 1;
  printf("test_c_api: PASS: %d checks failed\n", failures);
  return 0;
}
