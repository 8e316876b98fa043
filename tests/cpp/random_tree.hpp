// Seeded random models shared by the C++ tests and benchmarks.
//
// A model is first described in double precision as a list of BodySpec
// (joint kind, axes, placement, mass properties), then built for any scalar
// with build_model<S>. Building the same spec as ModelTpl<double> and
// ModelTpl<float> therefore gives two models whose parameters differ only by
// the rounding of the cast.
#pragma once
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>
#include <soadyn/soadyn.hpp>

namespace soadyn_test {

enum class JointKind { revolute, prismatic, helical, universal, cylindrical, planar, spherical, free, translation };

inline const std::vector<JointKind>& all_joint_kinds() {
  static const std::vector<JointKind> kinds = {JointKind::revolute,  JointKind::prismatic,   JointKind::helical,
                                               JointKind::universal, JointKind::cylindrical, JointKind::planar,
                                               JointKind::spherical, JointKind::free,      JointKind::translation};
  return kinds;
}

// One body of a tree, in double precision; `parent` is a body index (-1: world).
struct BodySpec {
  std::string name;
  int parent = -1;
  JointKind kind = JointKind::revolute;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // revolute, prismatic, helical, cylindrical; universal axis1
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitY();  // universal only, orthogonal to `axis`
  double pitch = 0.0;                                // helical only
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // joint frame in the parent frame
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double mass = 1.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_com = Eigen::Matrix3d::Identity();
};

using TreeSpec = std::vector<BodySpec>;

// Deterministic random numbers for model parameters and states.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  double normal() { return std::normal_distribution<double>()(engine_); }
  int integer(int lo, int hi_inclusive) { return std::uniform_int_distribution<int>(lo, hi_inclusive)(engine_); }
  bool coin(double p_true = 0.5) { return uniform(0.0, 1.0) < p_true; }

  Eigen::Vector3d unit_vector() {
    Eigen::Vector3d a(normal(), normal(), normal());
    return a.normalized();
  }
  Eigen::Vector3d uniform_vector3(double half_width) { return uniform_vector(3, half_width); }
  Eigen::VectorXd uniform_vector(int n, double half_width) {
    Eigen::VectorXd x(n);
    for (int k = 0; k < n; ++k) x[k] = uniform(-half_width, half_width);
    return x;
  }
  Eigen::Matrix3d rotation() {
    Eigen::Quaterniond quat(normal(), normal(), normal(), normal());
    return quat.normalized().toRotationMatrix();
  }
  // Rotational inertia about the centre of mass of a solid box of `mass`
  // with random sides in [side_lo, side_hi], randomly oriented.
  Eigen::Matrix3d box_inertia(double mass, double side_lo, double side_hi) {
    const double a = uniform(side_lo, side_hi), b = uniform(side_lo, side_hi), c = uniform(side_lo, side_hi);
    const Eigen::Vector3d principal = mass / 12.0 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b);
    const Eigen::Matrix3d R = rotation();
    return R * principal.asDiagonal() * R.transpose();
  }

 private:
  std::mt19937_64 engine_;
};

// Axes and pitch of a joint of `kind`, drawn at random.
inline void randomize_joint(BodySpec& body, Random& rng) {
  body.axis = rng.unit_vector();
  body.axis2 = body.axis.cross(rng.unit_vector()).normalized();
  body.pitch = body.kind == JointKind::helical ? rng.uniform(-0.3, 0.3) : 0.0;
}

// Mass ~1 kg, links ~`link_length`: well conditioned, so that float and
// double results can be compared at a tight tolerance.
inline void randomize_body(BodySpec& body, Random& rng, double link_length) {
  body.rotation = rng.rotation();
  body.translation = link_length * rng.unit_vector();
  body.mass = rng.uniform(0.5, 1.5);
  body.com = rng.uniform_vector3(0.5 * link_length);
  body.inertia_com = rng.box_inertia(body.mass, 0.5 * link_length, link_length);
}

// Joint kinds of the non-root bodies of a random tree: rounds of every kind
// but free, each round shuffled, so any 7 consecutive bodies from the first
// have every kind.
inline std::vector<JointKind> shuffled_joint_kinds(std::uint64_t seed, int count) {
  std::mt19937_64 shuffler(seed);
  std::vector<JointKind> kinds;
  while (static_cast<int>(kinds.size()) < count) {
    std::vector<JointKind> round;
    for (JointKind k : all_joint_kinds())
      if (k != JointKind::free) round.push_back(k);
    std::shuffle(round.begin(), round.end(), shuffler);
    kinds.insert(kinds.end(), round.begin(), round.end());
  }
  kinds.resize(static_cast<std::size_t>(count));
  return kinds;
}

// A random tree of `nbodies` bodies: the root is free and, from 8 bodies on,
// every other joint kind appears. Each body hangs off a random earlier body.
inline TreeSpec random_tree_spec(std::uint64_t seed, int nbodies, double link_length = 0.3) {
  Random rng(seed);
  const std::vector<JointKind> kinds = shuffled_joint_kinds(seed, nbodies - 1);
  TreeSpec tree(static_cast<std::size_t>(nbodies));
  for (int i = 0; i < nbodies; ++i) {
    BodySpec& body = tree[static_cast<std::size_t>(i)];
    body.name = "b" + std::to_string(i);
    body.parent = i == 0 ? -1 : rng.integer(0, i - 1);
    body.kind = i == 0 ? JointKind::free : kinds[static_cast<std::size_t>(i - 1)];
    randomize_joint(body, rng);
    randomize_body(body, rng, link_length);
  }
  return tree;
}

// A serial chain with the given joint kinds, body i hanging off body i - 1.
inline TreeSpec chain_spec(const std::vector<JointKind>& kinds, std::uint64_t seed, double link_length = 0.3) {
  Random rng(seed);
  TreeSpec chain(kinds.size());
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    BodySpec& body = chain[i];
    body.name = "b" + std::to_string(i);
    body.parent = static_cast<int>(i) - 1;
    body.kind = kinds[i];
    randomize_joint(body, rng);
    randomize_body(body, rng, link_length);
  }
  return chain;
}

template <class S>
soadyn::JointModel<S> make_joint(const BodySpec& body) {
  const soadyn::Vec3<S> axis = body.axis.cast<S>(), axis2 = body.axis2.cast<S>();
  switch (body.kind) {
    case JointKind::revolute: return soadyn::RevoluteJoint<S>{axis};
    case JointKind::prismatic: return soadyn::PrismaticJoint<S>{axis};
    case JointKind::helical: return soadyn::HelicalJoint<S>{axis, static_cast<S>(body.pitch)};
    case JointKind::universal: return soadyn::UniversalJoint<S>{axis, axis2};
    case JointKind::cylindrical: return soadyn::CylindricalJoint<S>{axis};
    case JointKind::planar: return soadyn::PlanarJoint<S>{};
    case JointKind::spherical: return soadyn::SphericalJoint<S>{};
    case JointKind::free: return soadyn::FreeJoint<S>{};
    case JointKind::translation: return soadyn::TranslationJoint<S>{};
  }
  return soadyn::FixedJoint<S>{};  // unreachable
}

// The model described by `spec`, in scalar S.
template <class S>
soadyn::ModelTpl<S> build_model(const TreeSpec& spec) {
  soadyn::ModelTpl<S> model;
  for (const BodySpec& body : spec) {
    soadyn::Transform<S> placement;
    placement.rotation = body.rotation.cast<S>();
    placement.translation = body.translation.cast<S>();
    model.add_body(body.name, body.parent, make_joint<S>(body), placement, static_cast<S>(body.mass),
                   body.com.cast<S>(), body.inertia_com.cast<S>());
  }
  return model;
}

// A state: configuration, velocities, inputs u (torques of regular DOFs,
// accelerations of prescribed ones) and external wrenches (nbodies x 6).
template <class S>
struct StateTpl {
  soadyn::VecX<S> q, v, u, f_ext;

  // The same state rounded to scalar T.
  template <class T>
  StateTpl<T> cast() const {
    return StateTpl<T>{q.template cast<T>(), v.template cast<T>(), u.template cast<T>(), f_ext.template cast<T>()};
  }
};
using State = StateTpl<double>;

// A random state of magnitude ~1 in double precision (soadyn's configuration
// sampler, then uniform velocities, inputs and wrenches in [-1, 1]).
// The soadyn functions take Eigen::Ref arguments from which S cannot be
// deduced, hence the explicit <double> here and in the tests.
inline State random_state(const soadyn::Model& model, std::uint64_t seed) {
  Random rng(seed);
  State s;
  s.q.resize(model.nq);
  soadyn::random_configuration<double>(model, seed, s.q);
  s.v = rng.uniform_vector(model.nv, 1.0);
  s.u = rng.uniform_vector(model.nv, 1.0);
  s.f_ext = rng.uniform_vector(6 * model.nbodies(), 1.0);
  return s;
}

// A prescribed/regular mask: each DOF prescribed with probability `p_prescribed`.
inline std::vector<bool> random_mask(int nv, Random& rng, double p_prescribed) {
  std::vector<bool> mask(static_cast<std::size_t>(nv));
  for (int dof = 0; dof < nv; ++dof) mask[static_cast<std::size_t>(dof)] = rng.coin(p_prescribed);
  return mask;
}

// A 7-DOF revolute arm: axes alternate z / y, links of 0.3 m along z.
inline TreeSpec seven_dof_arm_spec() {
  TreeSpec arm = chain_spec(std::vector<JointKind>(7, JointKind::revolute), 7);
  for (std::size_t i = 0; i < arm.size(); ++i) {
    arm[i].axis = i % 2 == 0 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
    arm[i].rotation.setIdentity();
    arm[i].translation = Eigen::Vector3d(0, 0, i == 0 ? 0.0 : 0.3);
  }
  return arm;
}

// Modal DOFs are always regular: the mask applies to hinge DOFs only.
template <class S>
void apply_mask(soadyn::ModelTpl<S>& model, const std::vector<bool>& mask) {
  for (int dof = 0; dof < model.nv; ++dof)
    model.set_prescribed(dof, mask[static_cast<std::size_t>(dof)] && !model.is_modal(dof));
}

// Adds flexible bodies to a model of at least four bodies: a hinged beam on
// body 3 with a rigid tool and a second beam (ball joint) on its tip, and a
// beam clamped to body 1: every way of attaching flexible bodies.
template <class S>
void add_flexible_bodies(soadyn::ModelTpl<S>& model) {
  const soadyn::FlexibleBodyTpl<S> beam = soadyn::cantilever_beam<S>(S(0.5), S(2), S(1), 2, 12);
  const soadyn::Transform<S> offset = soadyn::Transform<S>::Identity();
  model.add_flexible_body("flex_arm", model.body_names[3], soadyn::RevoluteJoint<S>{soadyn::Vec3<S>::UnitZ()}, offset,
                          beam);
  model.add_body("flex_tool", "flex_arm:tip", soadyn::RevoluteJoint<S>{soadyn::Vec3<S>::UnitY()}, offset, S(0.4),
                 soadyn::Vec3<S>(S(0.05), S(0), S(0)), soadyn::Mat3<S>(soadyn::Mat3<S>::Identity() * S(1e-3)));
  model.add_flexible_body("flex_tip", "flex_arm:tip", soadyn::SphericalJoint<S>{}, offset, beam);
  model.add_flexible_body("flex_panel", model.body_names[1], soadyn::FixedJoint<S>{}, offset, beam);
}

}  // namespace soadyn_test
