// Limits on the actuator commands a HIL controller sends: one magnitude per
// DOF and a policy for a command that exceeds one.
//
//   clamp   every value beyond its limit is set to the limit (saturation, as
//           an actuator does); the command is applied and counted as
//           saturated, per DOF;
//   reject  the whole command is discarded and counted; the previous command
//           stays applied;
//   stop    the run stops before the step, naming the first DOF at fault.
//
// Every entry of a command is judged, including those of DOFs that are
// prescribed when it arrives (their values are not applied, but a value out of
// range is a controller fault wherever it is).
//
// Default limits come from the model: a DOF's effort limit where the model
// has one (Model::set_effort_limit: URDF <limit effort>, MJCF forcerange or
// ctrlrange times gear); otherwise |tau_i| <= a * M_ii(q), with M_ii the
// diagonal of the joint-space mass matrix at the simulator's configuration q
// when the runner is built (the inertia moved by DOF i alone) and a =
// default_command_acceleration (1000 rad/s^2 or m/s^2 per DOF): enough to hold
// any link longer than 1.5 cm against gravity (a uniform link needs
// M_ii * 1.5 g / length), far below what makes a step non-finite. A DOF
// with no such scale (M_ii zero, as for a massless subtree, or not finite)
// gets no default limit (inf).
//
// Memory policy: the constructor and set_limits allocate; judge() allocates
// nothing and never throws. saturated() and rejected() may be read from any
// thread.
#pragma once
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "soadyn/algorithms/crba.hpp"
#include "soadyn/model/data.hpp"
#include "soadyn/model/model.hpp"

namespace soadyn {

enum class CommandPolicy { clamp, reject, stop };

inline const char* command_policy_name(CommandPolicy p) {
  switch (p) {
    case CommandPolicy::clamp: return "clamp";
    case CommandPolicy::reject: return "reject";
    case CommandPolicy::stop: return "stop";
  }
  return "?";
}

constexpr double default_command_acceleration = 1000.0;

// a * M_ii(q) for every DOF (see above).
inline Eigen::VectorXd default_command_limits(const Model& model, const Eigen::VectorXd& q,
                                              double acceleration = default_command_acceleration) {
  Data data(model);
  mass_matrix(model, data, q);  // a non-finite diagonal entry is handled below
  Eigen::VectorXd limits = acceleration * data.mass_matrix.diagonal();
  for (Eigen::Index k = 0; k < limits.size(); ++k) {
    if (!(limits[k] > 0.0) || !std::isfinite(limits[k])) limits[k] = std::numeric_limits<double>::infinity();
    const double effort = model.effort_limit[static_cast<std::size_t>(k)];
    if (std::isfinite(effort)) limits[k] = effort;
  }
  return limits;
}

class CommandLimits {
 public:
  enum class Verdict { within, saturated, rejected, stop };

  explicit CommandLimits(int nv)
      : limit_(Eigen::VectorXd::Constant(nv, std::numeric_limits<double>::infinity())),
        saturated_per_dof_(static_cast<std::size_t>(nv), 0) {}

  // Throws std::invalid_argument naming the first DOF index whose limit is
  // NaN or negative, or a size that is not nv. +inf: no limit.
  void set_limits(const Eigen::VectorXd& limits) {
    if (limits.size() != limit_.size())
      throw std::invalid_argument("command limits: expected " + std::to_string(limit_.size()) + " values, got " +
                                  std::to_string(limits.size()));
    for (Eigen::Index i = 0; i < limits.size(); ++i)
      if (!(limits[i] >= 0))
        throw std::invalid_argument("command limit of DOF " + std::to_string(i) + " must be >= 0, got " +
                                    std::to_string(limits[i]));
    limit_ = limits;
  }
  void set_policy(CommandPolicy policy) { policy_ = policy; }
  const Eigen::VectorXd& limits() const { return limit_; }
  CommandPolicy policy() const { return policy_; }

  // Judges `command` (finite values). within or saturated: `applied` holds
  // what to apply (clamped). rejected or stop: `applied` is untouched and
  // `dof` is the first DOF out of range.
  Verdict judge(const Eigen::VectorXd& command, Eigen::VectorXd& applied, int& dof) {
    dof = -1;
    for (Eigen::Index i = 0; i < command.size() && dof < 0; ++i)
      if (std::abs(command[i]) > limit_[i]) dof = static_cast<int>(i);
    if (dof < 0) {
      applied = command;
      return Verdict::within;
    }
    if (policy_ == CommandPolicy::reject) {
      rejected_.fetch_add(1, std::memory_order_relaxed);
      return Verdict::rejected;
    }
    if (policy_ == CommandPolicy::stop) return Verdict::stop;
    for (Eigen::Index i = 0; i < command.size(); ++i) {
      const bool over = std::abs(command[i]) > limit_[i];
      applied[i] = over ? std::copysign(limit_[i], command[i]) : command[i];
      saturated_per_dof_[static_cast<std::size_t>(i)] += over;
    }
    saturated_.fetch_add(1, std::memory_order_relaxed);
    return Verdict::saturated;
  }

  // Thread-safe: commands with at least one value clamped; commands rejected.
  std::uint64_t saturated() const { return saturated_.load(std::memory_order_relaxed); }
  std::uint64_t rejected() const { return rejected_.load(std::memory_order_relaxed); }
  const std::vector<std::uint64_t>& saturated_per_dof() const { return saturated_per_dof_; }

 private:
  Eigen::VectorXd limit_;
  CommandPolicy policy_ = CommandPolicy::clamp;
  std::atomic<std::uint64_t> saturated_{0}, rejected_{0};
  std::vector<std::uint64_t> saturated_per_dof_;
};

}  // namespace soadyn
