// Design sensitivity by forward-mode automatic differentiation
// (analysis/parameter_sensitivity.hpp): the one translation unit that
// instantiates the model, Data, hybrid_dynamics and constrained_dynamics for
// a dual-number scalar.

#include "dual_number.hpp"  // first: the scalar's traits precede every use

// The sweeps' definitions, instantiated here for the dual scalar, flexible
// bodies included (ModelTpl::cast converts them).
#include "soadyn/algorithms/aba.hxx"
#include "soadyn/constraints/constrained_dynamics.hxx"
#include "soadyn/algorithms/crba.hxx"
#include "soadyn/algorithms/hybrid.hxx"
#include "soadyn/algorithms/configuration.hxx"
#include "soadyn/algorithms/kinematics.hxx"
#include "soadyn/flex/flexible_body.hxx"
#include "soadyn/flex/modal_integrals.hxx"
#include "soadyn/analysis/parameter_sensitivity.hpp"
#include "soadyn/model/data.hxx"
#include "soadyn/model/model_cast.hxx"
#include "soadyn/model/parameters.hxx"

namespace soadyn {

namespace {

// A value and one directional derivative (dual_number.hpp).
using Dual = dual::DualNumber;

Dual seeded(double value, double derivative) { return Dual(value, derivative); }

enum class Kind { mass, com, inertia, placement, gravity, spring };

// Recognised by the entry's getter (parameters.hxx), not by its name.
Kind kind_of(const ParameterEntry<double>& e) {
  namespace p = parameter_detail;
  if (e.get == &p::get_mass<double>) return Kind::mass;
  if (e.get == &p::get_com<double>) return Kind::com;
  if (e.get == &p::get_inertia<double>) return Kind::inertia;
  if (e.get == &p::get_placement<double>) return Kind::placement;
  if (e.get == &p::get_gravity<double>) return Kind::gravity;
  if (e.get == &p::get_spring<double, 0> || e.get == &p::get_spring<double, 1> || e.get == &p::get_spring<double, 2>)
    return Kind::spring;
  throw ParameterError("parameter_sensitivity: parameter '" + e.name + "' has no derivative rule");
}

// The force elements' stiffness, damping and rest values of `model`, as constants.
void copy_spring_values(const Model& model, ModelTpl<Dual>& m) {
  const auto& from = model.force_elements;
  auto& to = m.force_elements;
  for (std::size_t k = 0; k < from.joint_springs.size(); ++k) {
    to.joint_springs[k].stiffness = Dual(from.joint_springs[k].stiffness);
    to.joint_springs[k].damping = Dual(from.joint_springs[k].damping);
    to.joint_springs[k].rest = Dual(from.joint_springs[k].rest);
  }
  for (std::size_t k = 0; k < from.point_springs.size(); ++k) {
    to.point_springs[k].stiffness = Dual(from.point_springs[k].stiffness);
    to.point_springs[k].damping = Dual(from.point_springs[k].damping);
    to.point_springs[k].rest_length = Dual(from.point_springs[k].rest_length);
  }
}

// The dual model's value of spring parameter `e` (parameters.hxx: spring_value).
Dual* spring_of(ModelTpl<Dual>& m, const ParameterEntry<double>& e) {
  namespace p = parameter_detail;
  const int field = e.get == &p::get_spring<double, 0> ? 0 : e.get == &p::get_spring<double, 1> ? 1 : 2;
  return p::spring_value(m, e.index, field);
}

Mat3<Dual> skew(const Vec3<Dual>& w) {
  Mat3<Dual> K;
  K << Dual(0.0), -w[2], w[1], w[2], Dual(0.0), -w[0], -w[1], w[0], Dual(0.0);
  return K;
}

}  // namespace

int parameter_directions(const ParameterEntry<double>& e) {
  return kind_of(e) == Kind::placement ? 6 : e.size();
}

struct ParameterSensitivity::Dual {
  explicit Dual(const Model& model)
      : model(model.cast<soadyn::Dual>()), data(this->model), q_start(model.nq), step(model.nv),
        f_ext(6 * model.nbodies()) {}
  ModelTpl<soadyn::Dual> model;
  DataTpl<soadyn::Dual> data;
  VecX<soadyn::Dual> q, v, u;
  VecX<soadyn::Dual> q_start, step, f_ext;  // state_derivatives' (sized once: no allocation per call)
};

ParameterSensitivity::ParameterSensitivity(const Model& model) : dual_(std::make_unique<Dual>(model)) {}
ParameterSensitivity::~ParameterSensitivity() = default;

void ParameterSensitivity::load(const Model& model) {
  using D = soadyn::Dual;
  ModelTpl<D>& m = dual_->model;
  for (std::size_t i = 0; i < model.mass.size(); ++i) {
    m.mass[i] = D(model.mass[i]);
    m.com[i] = model.com[i].cast<D>();
    m.inertia_com[i] = model.inertia_com[i].cast<D>();
    m.inertia[i] = model.inertia[i].cast<D>();
    m.placement[i].rotation = model.placement[i].rotation.cast<D>();
    m.placement[i].translation = model.placement[i].translation.cast<D>();
  }
  m.gravity = model.gravity.cast<D>();
  copy_spring_values(model, m);
  m.prescribed = model.prescribed;
  m.modes = model.modes;
  m.n_prescribed = model.n_prescribed;
  m.prescribed_dofs = model.prescribed_dofs;
  m.has_newton_euler_region = model.has_newton_euler_region;
  m.derived.tree_frame_reach_squared.assign(model.derived.tree_frame_reach_squared.begin(), model.derived.tree_frame_reach_squared.end());
  m.derived.check_tree_frame_reach = model.derived.check_tree_frame_reach;
  m.derived.reach_checks_needed = model.derived.reach_checks_needed;
}

Status ParameterSensitivity::compute(const Model& model, const ParameterTable<double>& table, int k,
                                     const ConstVecRef<double>& q, const ConstVecRef<double>& v,
                                     const ConstVecRef<double>& u, Eigen::Ref<MatX<double>> dqdd,
                                     Eigen::Ref<MatX<double>> dtau, Eigen::Ref<MatX<double>> dwrench,
                                     bool spanning_tree) {
  using D = soadyn::Dual;
  ModelTpl<D>& m = dual_->model;
  const ParameterEntry<double>& e = table.entry(k);
  const Kind kind = kind_of(e);
  const std::size_t b = static_cast<std::size_t>(std::max(e.index, 0));
  load(model);
  dual_->q = q.cast<D>();
  dual_->v = v.cast<D>();
  dual_->u = u.cast<D>();
  Status status;
  const int directions = parameter_directions(e);
  for (int j = 0; j < directions; ++j) {
    // Seed direction j (parameter_sensitivity.hpp), then restore below.
    switch (kind) {
      case Kind::mass: m.mass[b] = seeded(model.mass[b], 1.0); break;
      case Kind::com: m.com[b][j] = seeded(model.com[b][j], 1.0); break;
      case Kind::inertia: {
        const int r = j % 3, c = j / 3;
        m.inertia_com[b](r, c) = seeded(model.inertia_com[b](r, c), r == c ? 1.0 : 0.5);
        m.inertia_com[b](c, r) = seeded(model.inertia_com[b](c, r), r == c ? 1.0 : 0.5);
        break;
      }
      case Kind::placement:
        if (j < 3) {  // d/dt R exp([t e_j]x) at t = 0 is R [e_j]x
          Vec3<D> w = Vec3<D>::Zero();
          w[j] = seeded(0.0, 1.0);
          m.placement[b].rotation = model.placement[b].rotation.cast<D>() * (Mat3<D>::Identity() + skew(w));
        } else {
          m.placement[b].translation[j - 3] = seeded(model.placement[b].translation[j - 3], 1.0);
        }
        break;
      case Kind::gravity: m.gravity[j] = seeded(model.gravity[j], 1.0); break;
      case Kind::spring: {
        D* value = spring_of(m, e);
        *value = seeded(value->value(), 1.0);
        break;
      }
    }
    if (kind == Kind::mass || kind == Kind::com || kind == Kind::inertia)
      m.inertia[b] = spatial_inertia(m.mass[b], m.com[b], m.inertia_com[b]);  // M(k), Jain & Rodriguez 1993

    status = m.nloops() > 0 && !spanning_tree ? constrained_dynamics<D>(m, dual_->data, dual_->q, dual_->v, dual_->u)
                            : hybrid_dynamics<D>(m, dual_->data, dual_->q, dual_->v, dual_->u);
    for (int r = 0; r < model.nv; ++r) {
      dqdd(r, j) = dual_->data.qdd[r].derivative();
      dtau(r, j) = dual_->data.tau[r].derivative();
    }
    dwrench.col(j).setZero();
    for (int l = 0; l < (spanning_tree ? 0 : m.nloops()); ++l)
      for (int r = 0; r < 6; ++r)
        dwrench(6 * l + r, j) = dual_->data.loops.wrench[static_cast<std::size_t>(l)][r].derivative();

    // Back to constants.
    switch (kind) {
      case Kind::mass: m.mass[b] = D(model.mass[b]); break;
      case Kind::com: m.com[b] = model.com[b].cast<D>(); break;
      case Kind::inertia: m.inertia_com[b] = model.inertia_com[b].cast<D>(); break;
      case Kind::placement:
        m.placement[b].rotation = model.placement[b].rotation.cast<D>();
        m.placement[b].translation = model.placement[b].translation.cast<D>();
        break;
      case Kind::gravity: m.gravity = model.gravity.cast<D>(); break;
      case Kind::spring: copy_spring_values(model, m); break;
    }
    if (kind == Kind::mass || kind == Kind::com || kind == Kind::inertia) m.inertia[b] = model.inertia[b].cast<D>();
    if (!status.ok()) return status;
  }
  return status;
}

Status ParameterSensitivity::state_derivatives(const Model& model, const ConstVecRef<double>& q,
                                               const ConstVecRef<double>& v, const ConstVecRef<double>& u,
                                               const double* f_ext, Eigen::Ref<MatX<double>> dqdd_dq,
                                               Eigen::Ref<MatX<double>> dqdd_dv, Eigen::Ref<MatX<double>> dqdd_du,
                                               Eigen::Ref<MatX<double>> dtau_dq, Eigen::Ref<MatX<double>> dtau_dv,
                                               Eigen::Ref<MatX<double>> dtau_du, bool spanning_tree) {
  using D = soadyn::Dual;
  load(model);
  ModelTpl<D>& m = dual_->model;
  const int nv = model.nv;
  VecX<D>& q0 = dual_->q_start;
  VecX<D>& step = dual_->step;
  q0 = q.cast<D>();
  if (f_ext) dual_->f_ext = Eigen::Map<const VecX<double>>(f_ext, 6 * model.nbodies()).cast<D>();
  const D* f_dual = f_ext ? dual_->f_ext.data() : nullptr;
  dual_->q = q0;
  Status status;
  for (int x = 0; x < 3; ++x) {       // q, v, u
    for (int k = 0; k < nv; ++k) {
      dual_->v = v.cast<D>();
      dual_->u = u.cast<D>();
      if (x == 0) {  // q (+) e e_k, e dual
        step.setZero();
        step[k] = seeded(0.0, 1.0);
        integrate<D>(m, q0, step, D(1.0), dual_->q);
      } else {
        dual_->q = q0;
        (x == 1 ? dual_->v : dual_->u)[k] = seeded(x == 1 ? v[k] : u[k], 1.0);
      }
      status = m.nloops() > 0 && !spanning_tree
                   ? constrained_dynamics<D>(m, dual_->data, dual_->q, dual_->v, dual_->u, f_dual)
                              : hybrid_dynamics<D>(m, dual_->data, dual_->q, dual_->v, dual_->u, f_dual);
      if (!status.ok()) return status;
      Eigen::Ref<MatX<double>>& qdd_out = x == 0 ? dqdd_dq : x == 1 ? dqdd_dv : dqdd_du;
      Eigen::Ref<MatX<double>>& tau_out = x == 0 ? dtau_dq : x == 1 ? dtau_dv : dtau_du;
      for (int r = 0; r < nv; ++r) {
        qdd_out(r, k) = dual_->data.qdd[r].derivative();
        tau_out(r, k) = dual_->data.tau[r].derivative();
      }
    }
  }
  return status;
}

}  // namespace soadyn
