// The models and states of ../shared/tools/peer_bench, for the programs of
// bench/peer/: a URDF with a free-flyer root unless its path names ur5 or
// panda, and 64 random configurations, velocities and torques.
#pragma once
#include <pinocchio/parsers/urdf.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>

#include <string>
#include <vector>

struct PeerProblem {
  pinocchio::Model model;
  std::vector<Eigen::VectorXd> q, v, tau;
};

inline PeerProblem load_peer_problem(const std::string& path, int states = 64) {
  PeerProblem p;
  const bool free_flyer = path.find("ur5") == std::string::npos && path.find("panda") == std::string::npos;
  if (free_flyer)
    pinocchio::urdf::buildModel(path, pinocchio::JointModelFreeFlyer(), p.model);
  else
    pinocchio::urdf::buildModel(path, p.model);
  const Eigen::VectorXd bound = Eigen::VectorXd::Ones(p.model.nq);
  for (int k = 0; k < states; ++k) {
    p.q.push_back(pinocchio::randomConfiguration(p.model, -bound, bound));
    p.v.push_back(Eigen::VectorXd::Random(p.model.nv));
    p.tau.push_back(Eigen::VectorXd::Random(p.model.nv));
  }
  return p;
}
