// Pinocchio's ABA, RNEA and CRBA, each called through a function of its own
// that is never inlined (call_aba, call_rnea, call_crba), so that valgrind's
// callgrind can count the instructions inside the calls alone
// (bench/bench_instructions.py). The models and states are peer_bench's
// (../shared/tools/peer_bench: 64 random states; free-flyer root unless the
// path names ur5 or panda). Usage: pin_calls URDF aba|rnea|crba CALLS.
// Built by bench/peer/build.sh against the Pinocchio peer_bench installs.
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include "peer_problem.hpp"

#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

using namespace pinocchio;

__attribute__((noinline)) double call_aba(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                          const Eigen::VectorXd& tau) {
  return aba(m, d, q, v, tau)[0];
}
__attribute__((noinline)) double call_rnea(const Model& m, Data& d, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                           const Eigen::VectorXd& a) {
  return rnea(m, d, q, v, a)[0];
}
__attribute__((noinline)) double call_crba(const Model& m, Data& d, const Eigen::VectorXd& q) {
  return crba(m, d, q)(0, 0);
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: pin_calls URDF aba|rnea|crba CALLS\n";
    return 2;
  }
  const std::string path = argv[1], algorithm = argv[2];
  const long calls = std::atol(argv[3]);
  if (calls < 1) {
    std::cerr << "CALLS must be a positive integer, got " << argv[3] << "\n";
    return 2;
  }
  PeerProblem problem;
  try {
    problem = load_peer_problem(path);
  } catch (const std::exception& e) {
    std::cerr << path << ": " << e.what() << "\n";
    return 2;
  }
  const Model& m = problem.model;
  Data d(m);
  const int K = static_cast<int>(problem.q.size());
  double sink = 0;
  for (long i = 0; i < calls; ++i) {
    const int k = static_cast<int>(i % K);
    if (algorithm == "aba")
      sink += call_aba(m, d, problem.q[k], problem.v[k], problem.tau[k]);
    else if (algorithm == "rnea")
      sink += call_rnea(m, d, problem.q[k], problem.v[k], problem.tau[k]);
    else if (algorithm == "crba")
      sink += call_crba(m, d, problem.q[k]);
    else {
      std::cerr << "unknown algorithm " << algorithm << "\n";
      return 2;
    }
  }
  std::cout << sink << "\n";
}
