// The hinge update's terms of a leaf body whose articulated inertia and
// subspace are both constant in its root's frame (constant_tree_inertia.hxx:
// a reaction wheel turning about its axis of mass symmetry on a welded
// body). A leaf's articulated inertia P is its own inertia, so with its one
// DOF regular and no armature the terms of Jain & Rodriguez (1993), Eq. 28,
//   u = P H*,  D = H u,  G = u D^-1,  P+ = P - G u',
// are constants too: formed once per model, read by the sweeps. So are its
// subspace and its origin in that frame: the dynamics sweeps form no pose
// for it unless an external wrench or the hinge forces need its orientation
// (tree_frame_updates.hpp, tree_velocity_update).
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

template <class S>
struct ConstantHingeTerms {
  Vec6<S> gain = Vec6<S>::Zero();               // G
  S articulated_d = S(0);                       // D
  S inverse_d = S(0);                           // D^-1
  Mat6<S> articulated_plus = Mat6<S>::Zero();   // P+
  Vec6<S> subspace = Vec6<S>::Zero();           // H*, in the root's frame
  Vec3<S> origin = Vec3<S>::Zero();             // the leaf's origin in the root's frame
};

}  // namespace soadyn
