// The sines and cosines of a model's rotations about coordinate axes (the
// revolute_x/y/z kernels and axis-aligned universal joints,
// model.angle_coordinates), all in one pass before a
// tree-frame outward sweep, for the joint updates to read
// (tree_frame_updates.hpp). One pass takes four angles at a time: on x86
// processors with AVX2 and FMA, a polynomial kernel of our own, in registers
// (joint_angles.cpp); elsewhere glibc's vector math library (libmvec), two
// angles per call with SSE2. Computed one by one, sincos was a fifth of the
// mass matrix's time. Without either, and for other scalar types than
// double, the pass calls std::sin and std::cos.
#pragma once
#include <vector>

#include "soadyn/model/data.hpp"

namespace soadyn {

// Where the angle of slot k < n comes from: sign[k] * q[coordinate[k]]
// (model.angle_signs, angle_coordinates).
template <class S>
struct JointAngleSources {
  const S* q;
  const int* coordinate;
  const S* sign;
  Eigen::Index n;

  S operator[](Eigen::Index k) const { return q[coordinate[k]] * sign[k]; }
};

template <class S>
JointAngleSources<S> joint_angle_sources(const ModelTpl<S>& m, const S* q) {
  return {q, m.angle_coordinates.data(), m.angle_signs.data(), static_cast<Eigen::Index>(m.angle_coordinates.size())};
}

// Fills sweep.tree_joint_angle, tree_joint_sine and tree_joint_cosine for
// every slot of model.angle_coordinates. Allocation free. Double precision: the
// overload in joint_angles.cpp; other scalars one angle at a time.
void tabulate_joint_angles(const ModelTpl<double>& m, SweepData<double>& sweep, const double* q);

template <class S>
void tabulate_joint_angles(const ModelTpl<S>& m, SweepData<S>& sweep, const S* q) {
  using std::cos;
  using std::sin;
  const JointAngleSources<S> angles = joint_angle_sources(m, q);
  for (Eigen::Index k = 0; k < angles.n; ++k) {
    const S angle = angles[k];
    sweep.tree_joint_angle[k] = angle;
    sweep.tree_joint_sine[k] = sin(angle);
    sweep.tree_joint_cosine[k] = cos(angle);
  }
}

// Packets of four states (core/packet.hpp): the double kernel on the lanes'
// angles, so each lane's sines and cosines are the double call's, bit for
// bit (joint_angles.cpp).
template <>
void tabulate_joint_angles<Packet4d>(const ModelTpl<Packet4d>& m, SweepData<Packet4d>& sweep, const Packet4d* q);

// The double-precision kernel this process runs: "polynomial AVX2",
// "libmvec AVX2", "libmvec SSE2" or "std" (benchmarks report it). Chosen on
// the first call, or by this question if no call came first
// (FirstCallChoice, processor_features.hpp).
const char* joint_angle_kernel();

namespace detail {
// A kernel: the angles of `sources`, their sines and their cosines, into
// arrays of at least n rounded up to a multiple of four (the lanes past n get
// angle 0). The kernel reads the coordinates itself, into its vector
// registers: angles stored one by one and read back at once as a vector
// would stall store forwarding.
struct SineCosineKernel {
  const char* name;
  void (*run)(const JointAngleSources<double>& sources, double* angle, double* sine, double* cosine);
};
// Every kernel of this build that this processor can run, the chosen one
// first (the tests compare them all).
std::vector<SineCosineKernel> available_sine_cosine_kernels();
}  // namespace detail

}  // namespace soadyn
