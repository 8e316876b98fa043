#include "soadyn/analysis/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace soadyn {

namespace {

// The 2n roots grouped into n modes (see modes.hpp).
Eigen::MatrixXcd pair_roots(const Eigen::VectorXcd& roots) {
  const Eigen::Index n = roots.size() / 2;
  const double scale = std::max(roots.cwiseAbs().maxCoeff(), 1.0);
  std::vector<std::complex<double>> oscillating, real;
  for (Eigen::Index k = 0; k < roots.size(); ++k) {
    if (roots[k].imag() > 1e-9 * scale) oscillating.push_back(roots[k]);
    else if (std::abs(roots[k].imag()) <= 1e-9 * scale) real.emplace_back(roots[k].real(), 0.0);
  }
  std::stable_sort(real.begin(), real.end(), [](auto a, auto b) { return std::abs(a) < std::abs(b); });
  Eigen::MatrixXcd pairs(n, 2);
  Eigen::Index row = 0;
  for (const auto& r : oscillating) {
    if (row < n) pairs.row(row) << r, std::conj(r);
    ++row;
  }
  for (std::size_t k = 0; k + 1 < real.size(); k += 2) {
    if (row < n) pairs.row(row) << real[k], real[k + 1];
    ++row;
  }
  if (row != n) throw std::domain_error("modes: the roots of the linearised system do not pair into modes (stiffness or damping too large or too ill-conditioned for floating point)");
  return pairs;
}

}  // namespace

Modes modes(const Model& m, Data& d, DynamicsDerivatives& w, const ConstVecRef<double>& q, Status& status) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(m.nv);
  status = inverse_dynamics_derivatives<double>(m, d, w, q, zero, zero);
  if (!status.ok()) return Modes{};
  std::vector<int> regular;
  for (int k = 0; k < m.nv; ++k)
    if (!m.is_prescribed(k)) regular.push_back(k);
  return modes_of(d.mass_matrix, w.inverse_dq, w.inverse_dv, regular);
}

Modes modes_of(const Eigen::MatrixXd& mass_matrix, const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& damping,
               const std::vector<int>& dofs) {
  Modes out;
  out.dofs = dofs;
  const Eigen::Index n = static_cast<Eigen::Index>(out.dofs.size());
  out.angular_frequency.resize(n);
  out.damping_ratio.resize(n);
  out.roots.resize(n, 2);
  out.shapes.resize(n, n);
  if (n == 0) return out;  // every DOF prescribed: nothing oscillates
  Eigen::MatrixXd M(n, n), K(n, n), D(n, n);
  for (Eigen::Index r = 0; r < n; ++r)
    for (Eigen::Index c = 0; c < n; ++c) {
      M(r, c) = mass_matrix(out.dofs[r], out.dofs[c]);
      K(r, c) = stiffness(out.dofs[r], out.dofs[c]);
      D(r, c) = damping(out.dofs[r], out.dofs[c]);
    }
  const Eigen::LLT<Eigen::MatrixXd> mass(M);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -mass.solve(K);
  A.bottomRightCorner(n, n) = -mass.solve(D);
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(A);
  if (eigen.info() != Eigen::Success) throw std::domain_error("modes: the eigen-decomposition of the linearised system did not converge");
  const Eigen::VectorXcd roots = eigen.eigenvalues();
  if (!roots.allFinite()) throw std::domain_error("modes: the roots of the linearised system are not finite (the stiffness or damping is too large for floating point)");
  const Eigen::MatrixXcd pairs = pair_roots(roots);
  Eigen::VectorXd w2 = (pairs.col(0).array() * pairs.col(1).array()).real();
  const double scale = std::max(w2.cwiseAbs().maxCoeff(), 1.0);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  Eigen::VectorXd freq(n), zeta(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (std::abs(w2[k]) < 1e-9 * scale) w2[k] = 0.0;
    freq[k] = (w2[k] > 0 ? 1.0 : w2[k] < 0 ? -1.0 : 0.0) * std::sqrt(std::abs(w2[k]));
    zeta[k] = freq[k] != 0 ? -(pairs(k, 0) + pairs(k, 1)).real() / (2 * std::abs(freq[k])) : std::nan("");
  }
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return std::abs(freq[a]) < std::abs(freq[b]); });
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index j = order[static_cast<std::size_t>(k)];
    out.angular_frequency[k] = freq[j];
    out.damping_ratio[k] = zeta[j];
    out.roots.row(k) = pairs.row(j);
    Eigen::Index nearest = 0;
    (roots.array() - pairs(j, 0)).abs().minCoeff(&nearest);
    const Eigen::VectorXcd column = eigen.eigenvectors().col(nearest).head(n);
    Eigen::Index peak = 0;
    column.cwiseAbs().maxCoeff(&peak);
    const std::complex<double> scale_to_one = std::abs(column[peak]) > 0 ? 1.0 / column[peak] : 1.0;
    out.shapes.row(k) = (column * scale_to_one).real().transpose();
  }
  return out;
}

}  // namespace soadyn
