// Pinocchio's analytic derivatives timed with the peer_bench protocol
// (../shared/tools/peer_bench: median of 7 repetitions of N calls cycling
// through 64 random states; free-flyer root unless the path names ur5 or
// panda), for bench/bench_derivatives.py. Built by bench/peer/build.sh against
// the Pinocchio peer_bench installs.
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include "peer_problem.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <vector>

using namespace pinocchio;

template <class F>
double median_microseconds(F f, int calls) {
  std::vector<double> r;
  for (int rep = 0; rep < 7; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) f(i);
    r.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / calls);
  }
  std::sort(r.begin(), r.end());
  return r[3];
}

int main(int argc, char** argv) {
  const int calls = std::getenv("PEER_CALLS") ? std::atoi(std::getenv("PEER_CALLS")) : 5000;
  for (int a = 1; a < argc; ++a) {
    const std::string path = argv[a];
    const PeerProblem problem = load_peer_problem(path);
    const Model& m = problem.model;
    Data d(m);
    const std::vector<Eigen::VectorXd>& qs = problem.q;
    const std::vector<Eigen::VectorXd>& vs = problem.v;
    const std::vector<Eigen::VectorXd>& ts = problem.tau;
    const int K = static_cast<int>(qs.size());
    const double aba_d = median_microseconds([&](int i) { computeABADerivatives(m, d, qs[i % K], vs[i % K], ts[i % K]); }, calls);
    const double rnea_d = median_microseconds([&](int i) { computeRNEADerivatives(m, d, qs[i % K], vs[i % K], ts[i % K]); }, calls);
    std::cout << path.substr(path.rfind('/') + 1) << " nv=" << m.nv << " aba_derivatives=" << aba_d
              << "us rnea_derivatives=" << rnea_d << "us\n";
  }
}
