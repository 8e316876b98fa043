#include "soadyn/embed/plant.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "soadyn/sim/chart.hpp"

namespace soadyn::embed {

namespace {

constexpr char kStateMagic[4] = {'S', 'D', 'Y', 'S'};
constexpr std::uint32_t kStateVersion = 2;

// Sequential writes and reads of plain values through memcpy (no alignment assumed).
struct Writer {
  unsigned char* at;
  template <class T>
  void put(const T& x) {
    std::memcpy(at, &x, sizeof(T));
    at += sizeof(T);
  }
  void put_vector(const VecX<double>& x) {
    for (Eigen::Index k = 0; k < x.size(); ++k) put(x[k]);
  }
};

struct Reader {
  const unsigned char* at;
  bool finite = true;
  template <class T>
  T get() {
    T x;
    std::memcpy(&x, at, sizeof(T));
    at += sizeof(T);
    return x;
  }
  double get_double() {
    const double x = get<double>();
    finite = finite && std::isfinite(x);
    return x;
  }
  void get_vector(VecX<double>& x) {
    for (Eigen::Index k = 0; k < x.size(); ++k) x[k] = get_double();
  }
};

}  // namespace

Integrator integrator_from_name(const std::string& name) {
  if (name == "rk4") return Integrator::rk4;
  if (name == "euler") return Integrator::semi_implicit_euler;
  if (name == "dopri5") return Integrator::dopri5;
  throw std::invalid_argument("unknown integrator '" + name + "' (rk4, euler or dopri5)");
}

const char* input_kind_name(InputKind kind) {
  switch (kind) {
    case InputKind::acceleration: return "acceleration";
    case InputKind::velocity: return "velocity";
    case InputKind::position: return "position";
  }
  return "?";
}

InputKind input_kind_from_name(const std::string& name) {
  for (InputKind kind : {InputKind::acceleration, InputKind::velocity, InputKind::position})
    if (name == input_kind_name(kind)) return kind;
  throw std::invalid_argument("unknown input kind '" + name + "' (acceleration, velocity or position)");
}

Plant::Plant(const Model& model, double dt, Integrator integrator)
    : sim_(model, dt, integrator),
      u_(static_cast<std::size_t>(model.nv), 0.0),
      locked_(static_cast<std::size_t>(model.nv), 0),
      prescribed_(static_cast<std::size_t>(model.nv), 0),
      lockable_(static_cast<std::size_t>(model.nv), 0),
      sourceable_(static_cast<std::size_t>(model.nv), 0),
      kinds_(static_cast<std::size_t>(model.nv), InputKind::acceleration),
      body_wrenches_(VecX<double>::Zero(6 * model.nbodies())),
      qdd_(VecX<double>::Zero(model.nv)),
      tau_(VecX<double>::Zero(model.nv)),
      snapshot_(sim_.make_snapshot()),
      loaded_u_(u_),
      loaded_locked_(locked_),
      loaded_prescribed_(prescribed_) {
  for (int dof = 0; dof < model.nv; ++dof) {
    const std::size_t d = static_cast<std::size_t>(dof);
    lockable_[d] = lockable_dof(model, dof);
    sourceable_[d] = sourceable_dof(model, dof);
    prescribed_[d] = model.is_prescribed(dof) && sourceable_[d];
  }
  const Status s = apply_inputs();  // the model's prescribed DOFs follow their inputs (0) from the start
  if (!s.ok()) throw std::invalid_argument(sim_.describe(s));
}

bool lockable_dof(const Model& m, int dof) { return dof >= 0 && dof < m.nv && !m.is_modal(dof); }

bool sourceable_dof(const Model& m, int dof) {
  if (!lockable_dof(m, dof)) return false;
  for (int b = 0; b < m.nbodies(); ++b) {
    const int first = m.v_index[static_cast<std::size_t>(b)];
    if (dof >= first && dof < first + m.nv_body[static_cast<std::size_t>(b)])
      return joint_has_scalar_coordinates(m.joints[static_cast<std::size_t>(b)]);
  }
  return false;
}

void Plant::set_input_kind(int dof, InputKind kind) {
  if (!sourceable(dof))
    throw std::invalid_argument("DOF " + (dof >= 0 && dof < nv() ? "'" + model().dof_names[static_cast<std::size_t>(dof)] + "'"
                                                                 : std::to_string(dof)) +
                                " cannot follow its input (a modal DOF, or a joint without scalar coordinates)");
  kinds_[static_cast<std::size_t>(dof)] = kind;
}

int Plant::add_wrench_input(const std::string& name) {
  wrench_frames_.push_back(locate_frame<double>(model(), name));
  wrenches_.resize(wrenches_.size() + 6, 0.0);
  loaded_wrenches_ = wrenches_;
  return wrench_inputs() - 1;
}

namespace {

// The input source's acceleration and jerk that make a DOF at (q, v) follow its input u of `kind` over
// `horizon` (the Plant's header gives the three motions).
void input_motion(InputKind kind, double u, double q, double v, double horizon, double& a, double& jerk) {
  jerk = 0.0;
  if (kind == InputKind::acceleration) {
    a = u;
  } else if (kind == InputKind::velocity) {
    a = (u - v) / horizon;
  } else {  // cubic Hermite from (q, v) to (u, (u - q) / h): q(s) = q + v s + a s^2 / 2 + jerk s^3 / 6
    const double mean_rate = (u - q) / horizon;
    a = 4.0 * (mean_rate - v) / horizon;
    jerk = 6.0 * (v - mean_rate) / (horizon * horizon);
  }
}

}  // namespace

Status Plant::apply_inputs(double horizon) {
  if (!(horizon > 0.0)) horizon = sim_.dt();  // no step to come (advance(0)): plan over one step
  const Model& m = model();
  for (int dof = 0; dof < m.nv; ++dof) {
    const std::size_t d = static_cast<std::size_t>(dof);
    Status s;
    if (locked_[d] && lockable(dof)) {
      if (!m.is_prescribed(dof) || sim_.driven_by_input(dof)) s = sim_.lock(dof);  // not held yet
    } else if (prescribed_[d] && sourceable(dof)) {
      double a = 0.0, jerk = 0.0;
      const double q = sim_.q()[sim_.coordinate_of(dof)], v = sim_.v()[dof];
      input_motion(kinds_[d], u_[d], q, v, horizon, a, jerk);
      s = sim_.driven_by_input(dof) ? sim_.set_driven_acceleration(dof, a, jerk) : sim_.drive_by_input(dof, a, jerk);
    } else {
      if (m.is_prescribed(dof)) s = sim_.release(dof);
      if (s.ok()) sim_.set_input(dof, u_[d]);
    }
    if (!s.ok()) return s;
  }
  if (wrench_frames_.empty()) return Status{};
  body_wrenches_.setZero();
  for (std::size_t k = 0; k < wrench_frames_.size(); ++k) {
    const Eigen::Map<const Vec6<double>> wrench(wrenches_.data() + 6 * k);
    if (!wrench.allFinite()) return Status{StatusCode::non_finite_result, -1};
    const FrameLocation<double>& frame = wrench_frames_[k];
    body_wrenches_.segment<6>(6 * frame.body) += frame.placement.force_to_parent(wrench);
  }
  for (const FrameLocation<double>& frame : wrench_frames_)
    sim_.set_external_wrench(frame.body, body_wrenches_.segment<6>(6 * frame.body));
  return Status{};
}

int Plant::non_finite_input() const {
  for (std::size_t d = 0; d < u_.size(); ++d)
    if (!std::isfinite(u_[d])) return static_cast<int>(d);
  return -1;
}

int Plant::non_finite_wrench() const {
  for (std::size_t k = 0; k < wrenches_.size(); ++k)
    if (!std::isfinite(wrenches_[k])) return static_cast<int>(k / 6);
  return -1;
}

Status Plant::advance(int steps) {
  Status s = apply_inputs(steps * sim_.dt());
  for (int k = 0; k < steps && s.ok(); ++k) s = sim_.step();
  return s;
}

Status Plant::evaluate_outputs() { return sim_.evaluate_now(qdd_, tau_); }

std::size_t Plant::state_size() const {
  const std::size_t nq = static_cast<std::size_t>(this->nq()), nv = static_cast<std::size_t>(this->nv());
  return sizeof(kStateMagic) + sizeof(std::uint32_t) + 2 * sizeof(std::int32_t) + 3 * sizeof(double) +
         sizeof(std::int64_t) + nq * sizeof(double) +
         nv * (5 * sizeof(double) + 1 + sizeof(std::int32_t) + 5 * sizeof(double) + sizeof(double) + 2) +
         (static_cast<std::size_t>(snapshot_.external_wrenches.size()) + wrenches_.size()) * sizeof(double);
}

void Plant::save_state(unsigned char* out) const {
  sim_.save(snapshot_);
  Writer w{out};
  for (char c : kStateMagic) w.put(c);
  w.put(kStateVersion);
  w.put(static_cast<std::int32_t>(nq()));
  w.put(static_cast<std::int32_t>(nv()));
  w.put(snapshot_.time);
  w.put(snapshot_.energy_lost);
  w.put(snapshot_.adaptive_h);
  w.put(static_cast<std::int64_t>(snapshot_.steps));
  w.put_vector(snapshot_.q);
  for (const VecX<double>* x : {&snapshot_.v, &snapshot_.inputs, &snapshot_.forces, &snapshot_.source_offset,
                                &snapshot_.held_position})
    w.put_vector(*x);
  w.put_vector(snapshot_.external_wrenches);
  for (double x : wrenches_) w.put(x);
  for (std::size_t d = 0; d < snapshot_.drive.size(); ++d) {
    w.put(snapshot_.drive[d]);
    w.put(static_cast<std::int32_t>(snapshot_.source_of[d]));
    const InputMotion<double>& motion = snapshot_.input_motion[d];
    for (double x : {motion.t0, motion.q0, motion.v0, motion.a, motion.jerk}) w.put(x);
    w.put(u_[d]);
    w.put(locked_[d]);
    w.put(prescribed_[d]);
  }
}

bool Plant::load_state(const unsigned char* in, std::size_t size, const char** why) {
  if (size != state_size()) {
    *why = "the state has the wrong size for this model";
    return false;
  }
  Reader r{in};
  char magic[4];
  for (char& c : magic) c = r.get<char>();
  if (std::memcmp(magic, kStateMagic, sizeof(magic)) != 0) {
    *why = "not a soadyn simulator state (wrong magic)";
    return false;
  }
  if (r.get<std::uint32_t>() != kStateVersion) {
    *why = "a simulator state of another format version";
    return false;
  }
  if (r.get<std::int32_t>() != nq() || r.get<std::int32_t>() != nv()) {
    *why = "a simulator state of another model (nq, nv differ)";
    return false;
  }
  snapshot_.time = r.get_double();
  snapshot_.energy_lost = r.get_double();
  snapshot_.adaptive_h = r.get_double();
  snapshot_.steps = r.get<std::int64_t>();
  r.get_vector(snapshot_.q);
  for (VecX<double>* x : {&snapshot_.v, &snapshot_.inputs, &snapshot_.forces, &snapshot_.source_offset,
                          &snapshot_.held_position})
    r.get_vector(*x);
  r.get_vector(snapshot_.external_wrenches);
  for (double& x : loaded_wrenches_) x = r.get<double>();  // any double, as set_wrench takes
  bool in_range = snapshot_.steps >= 0 && snapshot_.adaptive_h > 0.0;
  const std::size_t n = snapshot_.drive.size();
  for (std::size_t d = 0; d < n; ++d) {
    snapshot_.drive[d] = r.get<std::uint8_t>();
    snapshot_.source_of[d] = r.get<std::int32_t>();
    InputMotion<double>& motion = snapshot_.input_motion[d];
    for (double* x : {&motion.t0, &motion.q0, &motion.v0, &motion.a, &motion.jerk}) *x = r.get_double();
    loaded_u_[d] = r.get<double>();  // any double, as set_u takes
    loaded_locked_[d] = r.get<std::uint8_t>();
    loaded_prescribed_[d] = r.get<std::uint8_t>();
    in_range = in_range && snapshot_.drive[d] <= 2 && loaded_locked_[d] <= 1 && loaded_prescribed_[d] <= 1 &&
               snapshot_.source_of[d] >= -1 && (snapshot_.drive[d] != 2 || snapshot_.source_of[d] >= 0);
  }
  if (!r.finite || !in_range) {
    *why = !r.finite ? "the simulator state holds a value that is not finite"
                     : "the simulator state holds a value out of range";
    return false;
  }
  if (!sim_.restore(snapshot_).ok()) {
    *why = "the simulator state names a motion source this simulator does not have";
    return false;
  }
  u_ = loaded_u_;  // same sizes: no allocation
  locked_ = loaded_locked_;
  prescribed_ = loaded_prescribed_;
  wrenches_ = loaded_wrenches_;
  return true;
}

}  // namespace soadyn::embed
