// The sines and cosines of a model's axis-aligned revolute joint angles (the
// revolute_x/y/z kernels, model.angle_bodies), all in one pass before a
// tree-frame outward sweep, for the joint steps to read
// (tree_frame_steps.hpp). One pass lets glibc's vector math library
// (libmvec) take four angles per call on processors with AVX2 and FMA, two
// with SSE2; computed one by one, sincos was a fifth of the mass matrix's
// time. Where the C library has no libmvec, and for other scalar types than
// double, the pass calls std::sin and std::cos.
#pragma once
#include <vector>

#include "soadyn/data.hpp"

namespace soadyn {

// sweep.tree_joint_angle: sign times coordinate, for every slot of model.angle_bodies.
template <class S>
void gather_joint_angles(const ModelTpl<S>& m, SweepData<S>& sweep, const S* q) {
  const std::size_t n = m.angle_bodies.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t body = static_cast<std::size_t>(m.angle_bodies[k]);
    sweep.tree_joint_angle[static_cast<Eigen::Index>(k)] = q[m.q_index[body]] * m.axis_sign[body];
  }
}

// Fills sweep.tree_joint_angle, tree_joint_sine and tree_joint_cosine for
// every slot of model.angle_bodies. Allocation free. Double precision: the
// overload in joint_angles.cpp; other scalars one angle at a time.
void tabulate_joint_angles(const ModelTpl<double>& m, SweepData<double>& sweep, const double* q);

template <class S>
void tabulate_joint_angles(const ModelTpl<S>& m, SweepData<S>& sweep, const S* q) {
  using std::cos;
  using std::sin;
  gather_joint_angles(m, sweep, q);
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(m.angle_bodies.size()); ++k) {
    sweep.tree_joint_sine[k] = sin(sweep.tree_joint_angle[k]);
    sweep.tree_joint_cosine[k] = cos(sweep.tree_joint_angle[k]);
  }
}

// The double-precision kernel this processor gets:
// "libmvec AVX2", "libmvec SSE2" or "std" (benchmarks report it).
const char* joint_angle_kernel();

namespace detail {
// A kernel: the sines and cosines of n angles, n a multiple of four.
struct SineCosineKernel {
  const char* name;
  void (*run)(const double* angle, double* sine, double* cosine, Eigen::Index n);
};
// Every kernel of this build that this processor can run, the chosen one
// first (the tests compare them all).
std::vector<SineCosineKernel> available_sine_cosine_kernels();
}  // namespace detail

}  // namespace soadyn
