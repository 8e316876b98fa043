// The model's derived caches: properties of its structure, parameters and
// flags that the sweeps read instead of recomputing on every call. They are
// derived data only, never input: ModelTpl::refresh_derived_caches rebuilds
// them after every change that can alter them (model.hpp), and a copy or a
// model file carries the inputs they are derived from.
#pragma once
#include <cstdint>
#include <vector>
#include "soadyn/flex/modal_integrals.hpp"
#include "soadyn/model/constant_hinge_terms.hpp"
#include "soadyn/spatial/inertia.hpp"
#include "soadyn/spatial/placement_axes.hpp"

namespace soadyn {

// What changed since the caches were refreshed (ModelTpl::refresh_derived_caches).
enum class DerivedChange {
  parameters,  // the structure, a placement, a mass or an inertia: every cache
  flags,       // the prescribed flags or the armature: the presummed leaves only
};

template <class S>
struct DerivedCachesTpl {
  // Tree frames' precision (tree_frame_reach.hxx): per body, the squared
  // distance from its tree origin within which the rigid sweeps may use tree
  // frames, and whether its distance can exceed it (then checked per call).
  std::vector<S> tree_frame_reach_squared;
  std::vector<std::uint8_t> check_tree_frame_reach;
  bool reach_checks_needed = false;

  // Inertias the dynamics sweeps and the CRBA need not form
  // (constant_tree_inertia.hxx): there a root whose joint has a constant
  // body-frame subspace (free, revolute or prismatic about a coordinate
  // axis, fixed) has its own body frame for its tree frame, so a rigid body
  // welded to it (through fixed joints), or turning on such a body about an
  // axis of symmetry of its mass (a reaction wheel, a turntable), has the
  // same inertia in its tree frame in every configuration. Per body: 1 when
  // it does, and then its ten inertia parameters in that frame. Floating-point
  // scalars only (an automatic-differentiation scalar keeps every inertia's
  // derivatives by forming it per call).
  std::vector<std::uint8_t> constant_tree_inertia;
  aligned_vector<InertiaParameters<S>> tree_inertia_parameters;
  // Per body, exact properties of its parameters that spare the sweeps and
  // the CRBA work on every call (refresh_constant_tree_inertia, run by every
  // change of a placement or an inertia; floating-point scalars only, else
  // none recorded, so that derivatives by those parameters stay right): the
  // shape of its placement's rotation (spatial/placement_axes.hpp: the
  // identity or a quarter-turn permutation of the axes spares the rotation
  // product of parent * placement), and whether its inertia about its centre
  // of mass is exactly diagonal (R I_c R' scales R's columns).
  std::vector<PlacementAxes<S>> placement_axes;
  std::vector<std::uint8_t> diagonal_inertia_com;
  // Likewise a flexible appendage welded to such a root (through fixed
  // joints): its pose in the root's frame is constant, so its modal
  // integrals are held in that frame too (ModalIntegrals::in_frame), and the
  // sweeps eliminate its modes there, with no congruence to the tree frame.
  // Per body: 1 for such an appendage; per flexible body (flexible_index):
  // its integrals in its root's body frame, where flagged.
  std::vector<std::uint8_t> appendage_in_root_frame;
  std::vector<ModalIntegrals<S>> root_frame_integrals;
  // And a leaf among the bodies with a constant inertia there that turns
  // about a coordinate axis (a reaction wheel) has a constant subspace too,
  // so its regular hinge update's D, G and P+ are constants
  // (constant_hinge_terms.hpp). Per body: 1 when they are, and the terms.
  std::vector<std::uint8_t> constant_leaf_hinge;
  aligned_vector<ConstantHingeTerms<S>> leaf_hinge_terms;
  // What such leaves add to their parent's articulated inertia is then
  // constant too: a regular constant leaf's P+ (above), and the P of a leaf
  // with a constant inertia whose DOFs are all prescribed (a turntable
  // driven at a rate), which it passes on unchanged (Eq. 28 with no regular
  // DOF). The tree-frame sweeps start the parent's P with their sum
  // (sweeps/tree_frame_sweeps.hxx), so no call adds them one by one.
  // Two sums, as the sweeps run under the model's prescribed flags (hybrid
  // dynamics) or with every DOF regular (forward dynamics). Per body:
  // leaf_plus_presummed, bit 0 (flags) and bit 1 (all regular) when its
  // term is in its parent's sum; leaf_presum_slot, the slot of its
  // children's sums (-1: none). The slots follow the structure; the sums
  // and bits follow the flags, armature and inertias (refresh_leaf_presums).
  std::vector<std::uint8_t> leaf_plus_presummed;
  std::vector<int> leaf_presum_slot;
  aligned_vector<Mat6<S>> leaf_presum_flags, leaf_presum_regular;

  // The refresh functions' scratch, kept so that a refresh allocates
  // nothing: the subtree radii and distance bounds of the reach; per body,
  // whether its pose in its root's body frame is constant, and that pose;
  // whether it has children (bit 1) and children on its nodes (bit 2).
  std::vector<S> subtree_radius, distance_bound;
  std::vector<std::uint8_t> welded_to_root, has_children;
  aligned_vector<Transform<S>> pose_in_root;
};

}  // namespace soadyn
