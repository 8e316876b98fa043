// The shared tails of the Python docstrings of calls on a state: the arguments' shapes and units, and
// what every such call checks and raises (bindings/arrays.cpp, errors.cpp). Adjacent string literals,
// so a docstring is one constant: "..." SOADYN_DOC_STATE SOADYN_DOC_RAISES.
#pragma once

#define SOADYN_DOC_STATE                                                                                    \
  "\n\nq: (nq,) coordinates (m, rad; a quaternion as x y z w), v: (nv,) velocities (m/s, rad/s; body-frame " \
  "for spherical, planar and free joints), accelerations (nv,) likewise per s; generalized forces (nv,) in N " \
  "for translations and N m for rotations; f_ext: None or (nbodies, 6) body-frame wrenches [torque N m; force " \
  "N] about each body origin. Units are SI throughout."

#define SOADYN_DOC_RAISES                                                                                   \
  "\n\nRaises TypeError for an argument that is not an array of real numbers; ValueError naming the "        \
  "argument and the coordinate or DOF for a wrong shape, a NaN or infinite entry or a quaternion off unit "  \
  "norm (soadyn.QUATERNION_TOLERANCE); DynamicsError naming the body or DOF when the result is not finite " \
  "(a singular articulated inertia, an input too large for floating point)."
