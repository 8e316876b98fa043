// What every joint header builds on: parameter checks that name the joint,
// the sampler of random configurations, and the fast-path tag.
//
// A joint type is one struct (revolute.hpp, ..., translation.hpp) with
//   name, description            type name ("revolute") and a one-line summary
//   Parameters, parameter_names  its constructor arguments, in member order
//   Space                        its configuration space: nq, nv, neutral,
//                                integrate, chart retract/rate, quaternion
//                                offset, scalar coordinates (vector_space.hpp,
//                                or a space defined in the joint's header)
//   nq, nv                       Space's sizes
//   translates                   whether it can move the body origin
//   coordinate_suffixes,         names of its coordinates and velocities
//   velocity_suffixes            (unused for one-DOF joints)
//   calc(q, v, pose, S, bias)    body-frame pose, motion subspace, bias S'v
//   fill_subspace(S)             the constant part of S (once, at Data creation)
//   random(sampler, q)           a random configuration
//   check(joint_name)            validates and normalises the parameters
// and optionally fast_path(sign), the tag of a dedicated fast path (joint_fast_path.hpp).
// joint_types.hpp registers it in the JointModel variant; joint.hpp
// dispatches every operation with std::visit.
#pragma once
#include <array>
#include <cstdint>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include "soadyn/joints/joint_fast_path.hpp"
#include "soadyn/joints/vector_space.hpp"
#include "soadyn/spatial/lie.hpp"
#include "soadyn/core/validation.hpp"

namespace soadyn {

// `axis` normalised; throws naming the joint when it is not finite or zero.
template <class S>
Vec3<S> checked_joint_axis(const Vec3<S>& axis, const std::string& joint, const char* which) {
  if (!axis.allFinite()) throw std::invalid_argument("joint '" + joint + "': " + which + " is not finite");
  const S n = axis.norm();
  if (!(n > detail::validation_tolerance<S>()))
    throw std::invalid_argument("joint '" + joint + "': " + which + " is zero");
  // In double precision an axis already unit to rounding is kept as given:
  // normalising is then idempotent, so a model rebuilt from its own
  // parameters (model files, which hold doubles) has the same axes bit for
  // bit. Other scalars (float models cast from double ones) always divide.
  if constexpr (std::is_same_v<S, double>) {
    if (std::abs(n - 1.0) <= 4.0 * std::numeric_limits<double>::epsilon()) return axis;
  }
  return axis / n;
}

// Draws of random configurations (algorithms/configuration.hxx): angles
// uniform in [-pi, pi], offsets uniform in [-1, 1], unit quaternions uniform
// on the sphere; deterministic for a given seed and model. The free,
// spherical, planar and cylindrical joints first `skip` a fixed number of
// angles: the seeded states of the tests and benchmarks (whose float-versus-
// double tolerances were set on them) are defined with those draws.
class CoordinateSampler {
 public:
  explicit CoordinateSampler(std::uint64_t seed) : rng_(seed) {}
  double angle() { return angle_(rng_); }
  void skip(int angles) {
    for (int k = 0; k < angles; ++k) angle();
  }
  double offset() { return offset_(rng_); }
  double uniform(double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng_); }
  // (x, y, z, w) from a normalised 4D Gaussian.
  template <class S>
  void unit_quaternion(S* q) {
    double g[4], n2 = 0;
    for (double& x : g) x = gauss_(rng_), n2 += x * x;
    for (int k = 0; k < 4; ++k) q[k] = S(g[k] / std::sqrt(n2));
  }

 private:
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> angle_{-M_PI, M_PI}, offset_{-1.0, 1.0};
  std::normal_distribution<double> gauss_;
};

}  // namespace soadyn
