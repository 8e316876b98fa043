#include "soadyn/embed/plant.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "soadyn/sim/chart.hpp"

namespace soadyn::embed {

namespace {

constexpr char kStateMagic[4] = {'S', 'D', 'Y', 'S'};
constexpr std::uint32_t kStateVersion = 1;

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

Plant::Plant(const Model& model, double dt, Integrator integrator)
    : sim_(model, dt, integrator),
      u_(static_cast<std::size_t>(model.nv), 0.0),
      locked_(static_cast<std::size_t>(model.nv), 0),
      prescribed_(static_cast<std::size_t>(model.nv), 0),
      lockable_(static_cast<std::size_t>(model.nv), 0),
      sourceable_(static_cast<std::size_t>(model.nv), 0),
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

Status Plant::apply_inputs() {
  const Model& m = model();
  for (int dof = 0; dof < m.nv; ++dof) {
    const std::size_t d = static_cast<std::size_t>(dof);
    Status s;
    if (locked_[d] && lockable(dof)) {
      if (!m.is_prescribed(dof) || sim_.driven_by_input(dof)) s = sim_.lock(dof);  // not held yet
    } else if (prescribed_[d] && sourceable(dof)) {
      s = sim_.driven_by_input(dof) ? sim_.set_driven_acceleration(dof, u_[d]) : sim_.drive_by_input(dof, u_[d]);
    } else {
      if (m.is_prescribed(dof)) s = sim_.release(dof);
      if (s.ok()) sim_.set_input(dof, u_[d]);
    }
    if (!s.ok()) return s;
  }
  return Status{};
}

int Plant::non_finite_input() const {
  for (std::size_t d = 0; d < u_.size(); ++d)
    if (!std::isfinite(u_[d])) return static_cast<int>(d);
  return -1;
}

Status Plant::advance(int steps) {
  Status s = apply_inputs();
  for (int k = 0; k < steps && s.ok(); ++k) s = sim_.step();
  return s;
}

Status Plant::evaluate_outputs() { return sim_.evaluate_now(qdd_, tau_); }

std::size_t Plant::state_size() const {
  const std::size_t nq = static_cast<std::size_t>(this->nq()), nv = static_cast<std::size_t>(this->nv());
  return sizeof(kStateMagic) + sizeof(std::uint32_t) + 2 * sizeof(std::int32_t) + 3 * sizeof(double) +
         sizeof(std::int64_t) + nq * sizeof(double) + nv * (5 * sizeof(double) + 1 + sizeof(std::int32_t) +
                                                             4 * sizeof(double) + sizeof(double) + 2);
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
  for (std::size_t d = 0; d < snapshot_.drive.size(); ++d) {
    w.put(snapshot_.drive[d]);
    w.put(static_cast<std::int32_t>(snapshot_.source_of[d]));
    const ConstantAcceleration<double>& motion = snapshot_.input_motion[d];
    w.put(motion.t0);
    w.put(motion.q0);
    w.put(motion.v0);
    w.put(motion.a);
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
  bool in_range = snapshot_.steps >= 0 && snapshot_.adaptive_h > 0.0;
  const std::size_t n = snapshot_.drive.size();
  for (std::size_t d = 0; d < n; ++d) {
    snapshot_.drive[d] = r.get<std::uint8_t>();
    snapshot_.source_of[d] = r.get<std::int32_t>();
    ConstantAcceleration<double>& motion = snapshot_.input_motion[d];
    motion.t0 = r.get_double();
    motion.q0 = r.get_double();
    motion.v0 = r.get_double();
    motion.a = r.get_double();
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
  return true;
}

}  // namespace soadyn::embed
