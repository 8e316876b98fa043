// Where tree frames keep their precision (templated implementation of
// ModelTpl::refresh_tree_frame_reach, model.hpp).
//
// The rigid sweeps carry every articulated inertia about its tree root's
// origin (sweeps/tree_frame_updates.hpp). For a body at distance L from
// that origin whose mass lies at an RMS radius r from its own origin, the
// hinge inertia D = H P H* (Jain & Rodriguez, "Recursive dynamics algorithm
// for multibody systems with prescribed motion", Eq. 28) of a rotational DOF is
// about m r^2 but is formed from terms of size m L^2: the tree frame loses
// (L / r)^2 of the precision. In body frames (the paper's own recursion) P
// is about the body's origin and nothing is lost. So each body gets a reach: the distance
// from its tree origin within which tree frames lose at most
// kTreeFrameReachRatio^2 epsilon (about 2e-10 in double) relative to the
// smallest body of its subtree; beyond it the dynamics run in body frames.
// Robots stay well inside (panda's fingertips, the worst of the benchmark
// robots, sit at about 300 RMS radii from its base); a 1e-4 m body 1 km from
// its root does not.
#pragma once
#include <cmath>
#include <limits>
#include "soadyn/model/model.hpp"

namespace soadyn {

// How many RMS radii of the smallest body in its subtree a body may sit from
// its tree origin before the rigid sweeps leave tree frames.
inline constexpr double kTreeFrameReachRatio = 1000.0;

template <class S>
void ModelTpl<S>::refresh_tree_frame_reach() {
  const std::size_t n = parent.size();
  const S infinity = std::numeric_limits<S>::infinity();
  // Smallest RMS radius, about its own origin, of a massive body in each subtree:
  // trace of the rotational inertia about the origin = 2 sum m |r|^2.
  std::vector<S>& radius = derived.subtree_radius;
  radius.assign(n, infinity);
  using std::sqrt;
  for (std::size_t i = 0; i < n; ++i)
    if (mass[i] > S(0)) radius[i] = sqrt(inertia[i].template topLeftCorner<3, 3>().trace() / (S(2) * mass[i]));
  for (std::size_t i = n; i-- > 0;)
    if (parent[i] >= 0) {
      S& r = radius[static_cast<std::size_t>(parent[i])];
      r = std::min(r, radius[i]);
    }
  // An upper bound on each body's distance from its tree origin in any configuration.
  std::vector<S>& distance_bound = derived.distance_bound;
  distance_bound.assign(n, S(0));
  derived.tree_frame_reach_squared.assign(n, infinity);
  derived.check_tree_frame_reach.assign(n, 0);
  derived.reach_checks_needed = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (parent[i] >= 0) {
      const bool unbounded = joint_translates(joints[i]) || attachment_node[i] >= 0;
      distance_bound[i] = unbounded ? infinity
                                    : distance_bound[static_cast<std::size_t>(parent[i])] + placement[i].translation.norm();
    }
    const S reach = S(kTreeFrameReachRatio) * radius[i];
    derived.tree_frame_reach_squared[i] = reach * reach;
    if (!(distance_bound[i] <= reach)) {
      derived.check_tree_frame_reach[i] = 1;
      derived.reach_checks_needed = true;
    }
  }
}

}  // namespace soadyn
