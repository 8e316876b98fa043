// The sweeps' small solves against Eigen's LLT and against
// cholesky_in_place: the free root's solves by LDL' (spd_factor6.hpp) and
// the two-DOF hinge step (body_updates.hpp), on random positive definite matrices
// (solutions, factors) and on singular ones (which pivot is named, and no
// inf or NaN on the way).
#include <cmath>
#include <cstdio>
#include <random>
#include "failure_count.hpp"
#include "soadyn/linalg/spd_factor6.hpp"
#include "soadyn/sweeps/body_updates.hpp"

using namespace soadyn;
using soadyn_test::check;

namespace {

// A random positive definite n x n matrix with condition number about 10^decades.
template <int N>
Eigen::Matrix<double, N, N> random_spd(std::mt19937& rng, double decades) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::Matrix<double, N, N> A;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) A(r, c) = unit(rng);
  const Eigen::HouseholderQR<Eigen::Matrix<double, N, N>> qr(A);
  const Eigen::Matrix<double, N, N> Q = qr.householderQ();
  Eigen::Matrix<double, N, 1> scales;
  for (int k = 0; k < N; ++k) scales[k] = std::pow(10.0, decades * (0.5 + 0.5 * unit(rng)));
  return Q * scales.asDiagonal() * Q.transpose();
}

void free_root_solve(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0.0;
  int cases = 0;
  for (int k = 0; k < 2000; ++k) {
    const Mat6<double> P = random_spd<6>(rng, 6.0);
    Vec6<double> b;
    for (int r = 0; r < 6; ++r) b[r] = unit(rng);
    Mat6<double> factor;
    const int bad = spd_factor6(P, detail::singular_pivot_threshold(P), factor);
    check(bad == -1, "a positive definite P accepted");
    const Vec6<double> x = spd_solve6(factor, b);
    const Eigen::LLT<Mat6<double>> llt(P);
    const Vec6<double> reference = llt.solve(b);
    const double cond = P.norm() * llt.solve(Mat6<double>::Identity()).norm();
    worst = std::max(worst, (x - reference).norm() / reference.norm() / cond);
    ++cases;
  }
  std::printf("spd_factor6: %d random P (condition up to 1e6), solve's max relative error / condition %.2e\n", cases,
              worst);
  check(worst < 1e-13, "spd_solve6 within 1e-13 x condition of LLT");
  // Singular P: the pivot named is cholesky_in_place's (a zero row k, every k).
  int agreed = 0;
  for (int zero = 0; zero < 6; ++zero) {
    Mat6<double> P = random_spd<6>(rng, 1.0);
    P.row(zero).setZero();
    P.col(zero).setZero();
    Mat6<double> factor, L = P;
    const int bad = spd_factor6(P, detail::singular_pivot_threshold(P), factor);
    agreed += bad == cholesky_in_place(L, detail::singular_pivot_threshold(P)) && bad == zero;
  }
  std::printf("spd_factor6: singular pivot named as by cholesky_in_place: %d of 6\n", agreed);
  check(agreed == 6, "every singular pivot named");
}

// The two-DOF step through articulated_hinge_update on P and a 6 x 2 subspace.
int two_dof(const Mat6<double>& P, const Eigen::Matrix<double, 6, 2>& s, Mat6N<double>& G, VecN<double>& nu,
            Mat6<double>& factor, Mat6<double>& P_plus) {
  const Mat6N<double> Sr = s;
  Vec6<double> z = Vec6<double>::Constant(0.3), z_plus;
  VecN<double> torque(2);
  torque << 1.0, -2.0;
  return detail::articulated_hinge_update<detail::PlusMode::store>(P, Sr, z, torque, static_cast<const double*>(nullptr), G, nu, factor,
                                                P_plus, z_plus);
}

void two_dof_hinge(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0.0;
  int close_factors = 0, cases = 0;
  for (int k = 0; k < 2000; ++k) {
    const Mat6<double> P = random_spd<6>(rng, 3.0);
    Eigen::Matrix<double, 6, 2> s;
    for (int r = 0; r < 6; ++r) s(r, 0) = unit(rng), s(r, 1) = unit(rng);
    Mat6N<double> G(6, 2);
    VecN<double> nu(2);
    Mat6<double> factor, P_plus;
    check(two_dof(P, s, G, nu, factor, P_plus) == -1, "a positive definite D accepted");
    const Eigen::Matrix<double, 6, 2> U = P * s;
    const Eigen::Matrix2d D = s.transpose() * U;  // as the step forms it
    const Eigen::Matrix<double, 6, 2> G_ref = (D.llt().solve((P * s).transpose())).transpose();
    worst = std::max(worst, (Eigen::Matrix<double, 6, 2>(G) - G_ref).norm() / G_ref.norm());
    Eigen::Matrix2d L = D;
    cholesky_in_place(L, detail::singular_pivot_threshold(P));
    const auto close = [](double x, double y) { return std::abs(x - y) <= 4e-16 * std::abs(y); };
    close_factors += close(factor(0, 0), L(0, 0)) && close(factor(1, 0), L(1, 0)) && close(factor(1, 1), L(1, 1));
    ++cases;
  }
  std::printf("two-DOF hinge: %d random D, max relative error of G %.2e, factors within 2 ulp of cholesky_in_place's: %d\n",
              cases, worst, close_factors);
  check(worst < 1e-10, "G within 1e-10 of LLT");
  check(close_factors == cases, "the stored factor is cholesky_in_place's");
  // D singular to within rounding, its entries far larger than P's diagonal:
  // the two forms of the second pivot differ by more than the threshold.
  // The step must call it singular, with no inf or NaN in the factor.
  Mat6<double> P = Mat6<double>::Identity();
  Eigen::Matrix<double, 6, 2> s = Eigen::Matrix<double, 6, 2>::Zero();
  const double a = 8.069528945079265, b = 18.476447384189626, c = 42.304713232226284;
  // s' s = D with P = 1: columns of lengths sqrt(a), sqrt(c) at the angle b / sqrt(a c).
  s(0, 0) = std::sqrt(a);
  s(0, 1) = b / std::sqrt(a);
  s(1, 1) = std::sqrt(std::max(0.0, c - b * b / a));
  Mat6N<double> G(6, 2);
  VecN<double> nu(2);
  Mat6<double> factor = Mat6<double>::Zero(), P_plus;
  const int bad = two_dof(P, s, G, nu, factor, P_plus);
  const bool finite = factor.allFinite();
  std::printf("two-DOF hinge: nearly singular D named pivot %d, factor finite: %s\n", bad, finite ? "yes" : "no");
  check(bad == 1 || (bad == -1 && finite && factor(1, 1) > 0.0), "a nearly singular D: singular, or a usable factor");
}

}  // namespace

int main() {
  std::mt19937 rng(2026);
  free_root_solve(rng);
  two_dof_hinge(rng);
  std::printf("%s: %d failures\n", soadyn_test::failures ? "FAIL" : "PASS", soadyn_test::failures);
  return soadyn_test::failures ? 1 : 0;
}
