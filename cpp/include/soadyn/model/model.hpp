// Model: immutable topology and parameters of a rigid multibody tree, plus
// the one run-time switch Jain & Rodriguez's algorithm needs, the prescribed/regular
// flag of every DOF. All per-call scratch lives in Data (data.hpp), so one
// Model can serve many Data objects on many threads as long as nobody flips
// flags concurrently.
//
// Layout: bodies are stored in topological order (parent < child). Body i
// owns the coordinates [q_index[i], q_index[i] + nq_body[i]) and the hinge
// DOFs [v_index[i], v_index[i] + nv_body[i]) of its joint, followed, for a
// flexible body (flex/flexible_body.hpp), by its n_modes[i] modal
// coordinates, which are both coordinates and DOFs: they start at
// modal_q_index(i) and modal_v_index(i). Blocks follow body order.
// Modal DOFs are named '<body>:mode<k>', k = 1..n_modes, and are always
// regular (their accelerations are unknowns of every dynamics call).
//
// A body added with a fixed joint is not a body of the tree: its mass,
// centre of mass and inertia are merged exactly into the body it is welded
// to, and its name stays usable as a parent (a "frame").
#pragma once
#include <array>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <string>
#include <unordered_map>
#include "soadyn/model/derived_caches.hpp"
#include "soadyn/flex/flexible_body.hpp"
#include "soadyn/model/force_element.hpp"
#include "soadyn/joints/joint.hpp"
#include "soadyn/joints/joint_fast_path.hpp"
#include "soadyn/model/loop.hpp"
#include "soadyn/spatial/inertia.hpp"
#include "soadyn/spatial/placement_axes.hpp"

namespace soadyn {

// A named frame rigidly attached to a body (body == -1: the world), or, with
// node >= 0, the frame of attachment node `node` of a flexible body (it moves
// with the deformation; `placement` is then in the node frame).
template <class S>
struct Frame {
  std::string name;
  int body = -1;
  Transform<S> placement;  // frame in the body frame
  int node = -1;
};

// What add_body requires of a body's inertia. Every body's spatial inertia
// (mass, mass * com, inertia about the frame origin) must be finite, its mass
// non-negative and its inertia symmetric, always. require_physical (the
// default) also requires a rigid body that can exist: inertia about the centre
// of mass positive semidefinite, principal moments obeying the triangle
// inequality, no inertia without mass, each within a rounding tolerance
// relative to the inertia's scale (see check_physical_inertia in model.hxx).
// accept_nonphysical skips these physical tests, as an explicit opt-in for
// data the user knows to be wrong (the dynamics may then be singular).
enum class InertiaPolicy { require_physical, accept_nonphysical };

// Thrown when a body (or a body with parts welded to it) has a finite but
// physically impossible inertia under InertiaPolicy::require_physical.
struct NonphysicalInertiaError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Per-body view of the DOF flags, derived from the per-DOF flags.
struct HingeModes {
  std::uint8_t n_regular = 0;
  std::uint8_t n_prescribed = 0;
  std::uint8_t regular[6] = {};     // local indices of regular DOFs
  std::uint8_t prescribed[6] = {};  // local indices of prescribed DOFs
  // True when some hinge on the path from the root to this body (inclusive)
  // is regular: only then does the body need an articulated inertia P.
  // Bodies without one are handled as in inverse dynamics (RNEA).
  bool needs_articulated_inertia = true;
  // True when some DOF of this hinge has a nonzero armature (ModelTpl::armature).
  bool has_armature = false;
};

// Which sweeps forward dynamics, hybrid dynamics and its impulse form run
// (sweeps/dynamics_path.hxx), fixed by the model's structure and stored
// when it changes. A tree-frame path falls back to body frames for a call in
// which a body lies beyond its tree-frame reach (tree_frame_reach.hxx).
// The models whose loops constrained_dynamics solves through the mass matrix
// (ModelTpl::loops_through_mass_matrix): those whose tree-sparse factor of M
// costs at most this much (ModelTpl::tree_factor_work) per loop equation.
// The constant separates the models on which the mass-matrix path is the
// faster (docs/performance.md, closed loops).
constexpr int kMassMatrixLoopsWorkPerEquation = 300;

enum class DynamicsPath : std::uint8_t {
  rigid_tree_frames,      // no flexible body: tree frames, rigid updates only
  appendage_tree_frames,  // flexible bodies with no body on a node: tree frames
  body_frames,            // some body on a flexible body's node: body frames
};

template <class S>
class ModelTpl {
 public:
  ModelTpl();

  // Adds a body attached to `parent` (a body or frame name; "" or "world"
  // for the world) through `joint` placed at `placement` in the parent's
  // frame. `inertia_com` is about the centre of mass, in the body frame.
  // `joint_name` defaults to the body name. Returns the body index, or -1 for
  // a fixed joint (the body becomes a frame, its inertia merged into the
  // parent's, which must then pass `policy`). Throws std::invalid_argument
  // naming the body or joint at fault (NonphysicalInertiaError for an
  // impossible inertia).
  int add_body(const std::string& name, const std::string& parent, const JointModel<S>& joint,
               const Transform<S>& placement, S mass, const Vec3<S>& com, const Mat3<S>& inertia_com,
               const std::string& joint_name = "", InertiaPolicy policy = InertiaPolicy::require_physical);
  // Same with the parent given by body index (-1: the world).
  int add_body(const std::string& name, int parent, const JointModel<S>& joint,
               const Transform<S>& placement, S mass, const Vec3<S>& com, const Mat3<S>& inertia_com,
               const std::string& joint_name = "", InertiaPolicy policy = InertiaPolicy::require_physical);
  // Adds a flexible body: its reference frame is the joint frame (as for a
  // rigid body), its mass is the flexible body's nodes, and its modal
  // coordinates follow the joint's DOFs. A fixed joint clamps it to the
  // parent (it stays a body, with modal DOFs only). Every attachment node
  // becomes a frame '<name>:<attachment>' that children can use as parent.
  // Bodies cannot be welded (fixed joint) to a flexible body: give the mass
  // to its nodes instead.
  int add_flexible_body(const std::string& name, const std::string& parent, const JointModel<S>& joint,
                        const Transform<S>& placement, const FlexibleBodyTpl<S>& body,
                        const std::string& joint_name = "");

  // Adds a closed loop (model/loop.hpp): a cut joint of `kind` between frame
  // A, `placement_a` in the frame of body or frame `frame_a`, and frame B,
  // `placement_b` in the frame of `frame_b` ("" or "world": the world).
  // `length` is the rod length of a "distance" loop (finite, positive) and
  // ignored otherwise; 0 means the current length: the distance between the
  // two frames at `configuration` (nq coordinates), or at the neutral
  // configuration when it is null. Loops on a flexible body, or on a body
  // carried by one, are refused. Throws LoopError naming the loop (unknown
  // frame, a loop between a body and itself, a non-finite or non-orthonormal
  // placement, a duplicate name, a bad length, frames that coincide where the
  // length is measured). Returns the loop's index.
  int add_loop(const std::string& name, const std::string& frame_a, const std::string& frame_b, LoopKind kind,
               const Transform<S>& placement_a, const Transform<S>& placement_b, S length = S(0),
               const S* configuration = nullptr);
  int nloops() const { return static_cast<int>(loops.size()); }
  int loop_index(const std::string& name) const;

  // Force elements (model/force_element.hpp). A joint spring on
  // velocity index `dof`; a point spring between point_a, in the frame of
  // body or frame `frame_a`, and point_b in `frame_b` ("" or "world": the
  // world), rest_length null: the length at the neutral configuration, an
  // optional force law table (empty vectors: none). Throw
  // std::invalid_argument naming the element (duplicate name, unknown frame or
  // DOF, a DOF without scalar coordinate, negative or non-finite constants, a
  // bad table). Return the element's index in its list.
  int add_joint_spring(const std::string& name, int dof, S stiffness, S damping = S(0), S rest = S(0));
  int add_point_spring(const std::string& name, const std::string& frame_a, const std::string& frame_b,
                       const Vec3<S>& point_a, const Vec3<S>& point_b, S stiffness, S damping = S(0),
                       const S* rest_length = nullptr, const std::vector<S>& law_lengths = {},
                       const std::vector<S>& law_forces = {});
  bool has_force_elements() const { return !force_elements.empty(); }

  int nbodies() const { return static_cast<int>(parent.size()); }
  bool has_flexible_bodies() const { return !flexible_bodies.empty(); }
  bool is_flexible(int body) const { return flexible_index[static_cast<std::size_t>(body)] >= 0; }
  const FlexibleBodyTpl<S>& flexible_body(int body) const {
    return flexible_bodies[static_cast<std::size_t>(flexible_index[static_cast<std::size_t>(body)])];
  }
  int modal_q_index(int body) const { return q_index[static_cast<std::size_t>(body)] + nq_body[static_cast<std::size_t>(body)]; }
  int modal_v_index(int body) const { return v_index[static_cast<std::size_t>(body)] + nv_body[static_cast<std::size_t>(body)]; }
  bool is_modal(int dof) const { return modal_dof[static_cast<std::size_t>(dof)] != 0; }

  // Prescribed (true) or regular (false) flag of velocity index `dof`.
  // Allocation free and O(n): only the per-body views are refreshed.
  // Throws std::invalid_argument for a modal DOF (always regular).
  void set_prescribed(int dof, bool flag);
  // Every hinge DOF; modal DOFs stay regular.
  void set_all_prescribed(bool flag);
  bool is_prescribed(int dof) const { return prescribed[static_cast<std::size_t>(dof)] != 0; }

  // Armature of velocity index `dof`: a rotor inertia on the DOF itself (a
  // motor's inertia reflected through its gearbox, MuJoCo's `armature`). The
  // mass matrix carries it on its diagonal, so the hinge equation becomes
  // T_k = H_k f + armature_k qdd_k, and kinetic energy gains
  // armature_k v_k^2 / 2; momenta do not. Finite and non-negative; modal
  // DOFs have none. Throws std::invalid_argument naming the DOF. Allocation free.
  void set_armature(int dof, S value);

  // Effort limit of velocity index `dof`: the largest force or torque its
  // actuator can apply (URDF <limit effort>, MJCF forcerange or ctrlrange
  // times gear), +inf (the default) when unknown. HIL runs take it as the
  // DOF's command limit (sim/command_limits.hpp). Positive (+inf allowed);
  // throws std::invalid_argument naming the DOF. Allocation free.
  void set_effort_limit(int dof, S value);

  // Refreshes the derived caches (`derived`) after `change`: a structural
  // change or a change of mass, com, inertia_com / inertia or placement
  // (parameters.hpp) refreshes them all (the tree-frame reach, the constant
  // tree-frame inertias, the constant leaf hinges and their presums); a
  // change of the prescribed flags or the armature only the presums.
  // Allocation free once the structure is set.
  void refresh_derived_caches(DerivedChange change = DerivedChange::parameters) {
    if (change == DerivedChange::flags) {
      refresh_leaf_presums();
      return;
    }
    refresh_tree_frame_reach();
    refresh_constant_tree_inertia();  // then the constant leaf hinges and the presums
  }

  // Name lookups; -1 when absent.
  int body_index(const std::string& name) const;
  int dof_index(const std::string& name) const;
  int frame_index(const std::string& name) const;

  // Per body, in topological order.
  std::vector<std::string> body_names;
  std::vector<std::string> joint_names;
  std::vector<int> parent;
  std::vector<JointModel<S>> joints;
  aligned_vector<Transform<S>> placement;  // joint frame in the parent body frame
  aligned_vector<Mat6<S>> inertia;         // spatial inertia about the body origin (M(k), Jain & Rodriguez 1993)
  std::vector<S> mass;
  aligned_vector<Vec3<S>> com;
  aligned_vector<Mat3<S>> inertia_com;     // rotational inertia about the centre of mass, body frame
  std::vector<JointFastPath> joint_fast_path;   // joints/joint_fast_path.hpp
  std::vector<S> axis_sign;                // +-1: the axis of an axis-aligned revolute or prismatic joint is axis_sign e_k
  // Rotations about coordinate axes (the revolute_x/y/z fast paths, and both
  // rotations of a universal joint whose axes are coordinate axes) have their
  // sines and cosines computed together before each tree-frame sweep
  // (sweeps/joint_angles.hpp): per body, its first slot in that table
  // (-1: none); per slot, the coordinate (index into q) and the sign of its
  // angle: angle = angle_signs[k] q[angle_coordinates[k]].
  std::vector<int> angle_slot, angle_coordinates;
  std::vector<S> angle_signs;
  std::vector<int> q_index, v_index, nq_body, nv_body;
  std::vector<HingeModes> modes;
  // Flexible bodies: index into flexible_bodies (-1: rigid), modal
  // coordinate count (0: rigid), and the node of a flexible parent this
  // body's joint is placed on (-1: the parent's body frame; `placement` is
  // then in the node frame).
  std::vector<int> flexible_index, n_modes, attachment_node;
  std::vector<FlexibleBodyTpl<S>> flexible_bodies;

  // Per DOF / coordinate.
  int nq = 0, nv = 0;
  std::vector<std::string> dof_names, coordinate_names;
  std::vector<int> dof_body;
  // The previous DOF on each DOF's path to the root (-1: none): the mass
  // matrix couples a DOF only with its ancestors and descendants (branch-
  // induced sparsity, linalg/tree_cholesky.hpp).
  std::vector<int> dof_parent;
  // The first DOF of the unbranched run of consecutive DOFs ending at each DOF
  // (dof_parent[k] == k - 1 throughout the run): ancestors walked as segments.
  std::vector<int> dof_run_start;
  std::vector<std::uint8_t> prescribed;
  std::vector<std::uint8_t> modal_dof;  // 1 for modal coordinates
  std::vector<S> armature;              // per DOF, zero by default (set_armature)
  bool has_armature = false;            // some DOF's armature is nonzero
  std::vector<S> effort_limit;          // per DOF, +inf by default (set_effort_limit)
  int n_prescribed = 0;  // how many DOFs are prescribed
  // The first n_prescribed entries: the prescribed DOFs in increasing order
  // (sized nv when DOFs are added, rewritten in place when a flag flips).
  std::vector<int> prescribed_dofs;
  // True when some body needs no articulated inertia (HingeModes): the root
  // region of a fixed-base tree whose hinges are all prescribed.
  bool has_newton_euler_region = false;

  // What the sweeps read instead of recomputing per call: properties derived
  // from the structure, the parameters and the flags (derived_caches.hpp),
  // refreshed by refresh_derived_caches.
  DerivedCachesTpl<S> derived;

  // Set by every structural change (add_body, add_flexible_body); a copy carries it.
  DynamicsPath dynamics_path = DynamicsPath::rigid_tree_frames;
  // The work of factoring M with the tree's sparsity (tree_cholesky.hpp), up
  // to a constant: the sum over DOFs of the square of their count of
  // ancestors-or-self. Set with dynamics_path.
  std::size_t tree_factor_work = 0;
  // Whether constrained_dynamics solves the loops through the mass matrix
  // (CRBA, its tree-sparse factor) rather than by the articulated-body
  // response to unit multipliers: rigid models whose factor is cheap for
  // their number of loop equations (kMassMatrixLoopsWorkPerEquation), where
  // the articulated sweeps' per-body constants and the response's load
  // cases cost more. Models with flexible bodies always take the mass matrix.
  // In single precision, rigid models keep the articulated path: on the
  // ill-conditioned cases of the float-versus-double test of the loops
  // (cond(M_rr) up to 2e3), the mass-matrix path's largest error was 1.3e-4
  // where the articulated path's stays below 9e-5.
  bool loops_through_mass_matrix() const {
    return !std::is_same<S, float>::value && dynamics_path == DynamicsPath::rigid_tree_frames &&
           tree_factor_work <= static_cast<std::size_t>(kMassMatrixLoopsWorkPerEquation) *
                                   static_cast<std::size_t>(nloop_equations);
  }

  std::vector<Frame<S>> frames;
  // Closed loops, in the order added, and their equation count (the sum of
  // their rows(); each loop's equations start at its first_row).
  std::vector<LoopTpl<S>> loops;
  int nloop_equations = 0;
  // Springs and dampers, in the order added; their constants may be changed in place.
  ForceElementsTpl<S> force_elements;
  Vec3<S> gravity;
  // What describes the model without entering the dynamics (how it is drawn,
  // where it came from): a JSON object as text, kept by model files
  // (model_file.hpp) and read by viewers. "{}" when there is none.
  std::string description = "{}";
  // Incremented by every structural change (Data must then be rebuilt).
  std::uint64_t version = 0;

  // The same model in scalar T (model_cast.hxx), e.g. an automatic-
  // differentiation scalar. Flexible bodies are converted, not validated
  // again (FlexibleBodyTpl::converted).
  template <class T>
  ModelTpl<T> cast() const;
  // Models of one structure as one model `out` of packets T of N lanes
  // (model_cast.hxx): lane l of every value is models[l]'s, the rest the
  // first model's (names, joints, flexible bodies, frames, loops: no
  // parameter changes them). False when the models' structure or flags
  // differ (`out` is then not to be used). N = 1: cast().
  template <class T, std::size_t N>
  static bool cast_into(const std::array<const ModelTpl*, N>& models, ModelTpl<T>& out);
  // The values and flags of `models` (masses, placements, gravity, springs,
  // prescribed flags, ...) taken again into `out`, which cast_into made from
  // models of this structure: names, joints, frames and loops are left as
  // they are, and nothing is allocated (every array keeps its size). False
  // when the flags differ between the models.
  template <class T, std::size_t N>
  static bool cast_values_into(const std::array<const ModelTpl*, N>& models, ModelTpl<T>& out);

 private:
  template <class>
  friend class ModelTpl;
  void refresh_modes();
  void refresh_body_modes(int body);
  void refresh_tree_frame_reach();
  void refresh_constant_tree_inertia();
  void refresh_constant_leaf_hinges();
  void refresh_leaf_presums();  // allocation free once the structure is set
  void refresh_dynamics_path();
  // add_body / add_flexible_body after the parent is resolved; `flexible`
  // null for a rigid body.
  int add_resolved(const std::string& name, int parent_body, int node, const JointModel<S>& joint,
                   const Transform<S>& placement, S mass, const Vec3<S>& com, const Mat3<S>& inertia_com,
                   const std::string& joint_name, const FlexibleBodyTpl<S>* flexible, InertiaPolicy policy);
  // The body and the placement in its frame of loop frame `frame` ("" or
  // "world": body -1); throws LoopError naming `loop`.
  int resolve_loop_frame(const std::string& loop, const std::string& frame, const Transform<S>& placement,
                         const char* which, Transform<S>& in_body) const;
  std::unordered_map<std::string, int> body_lookup_, dof_lookup_, frame_lookup_;
};

using Model = ModelTpl<double>;
using ModelF = ModelTpl<float>;
extern template class ModelTpl<double>;
extern template class ModelTpl<float>;

}  // namespace soadyn
