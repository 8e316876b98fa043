// Per-call buffers of the loop layer (model/loop.hpp), sized once from the
// Model's loops (m = nloop_equations): part of DataTpl as `data.loops`.
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/QR>
#include "soadyn/linalg/semidefinite_solve.hpp"
#include "soadyn/model/model.hpp"

namespace soadyn {

template <class S> using Mat6X = Eigen::Matrix<S, 6, Eigen::Dynamic>;

// Changes of the hybrid sweeps' quantities caused by loop wrenches
// (articulated_loop_response.hxx), one column per load case: per body a
// 6 x cases block (body i's at columns i * cases) of the change of z
// (Eq. 28) and of alpha (Eq. 29); per DOF (rows) the change of eps, then of
// nu = D^-1 eps (the regular DOFs of a hinge in their local order), and of qdd.
// Bodies of different trees (the subtrees of different root bodies) are
// coupled only through loops, so a load case moves only the trees of its
// loop's two bodies: per body, the response is computed for its tree's
// cases, [first_case, first_case + case_count) (the loops with a body in the
// tree, first to last), and stays zero, as constructed, in the others (a
// parallel robot's legs each see their own loop's cases only).
template <class S>
struct ArticulatedResponse {
  explicit ArticulatedResponse(const ModelTpl<S>& model)
      : cases(model.nloop_equations), z(Mat6X<S>::Zero(6, model.nbodies() * cases)),
        alpha(Mat6X<S>::Zero(6, model.nbodies() * cases)), eps(MatX<S>::Zero(model.nv, cases)),
        qdd(MatX<S>::Zero(model.nv, cases)), first_case(static_cast<std::size_t>(model.nbodies()), 0),
        case_count(static_cast<std::size_t>(model.nbodies()), 0) {
    const std::size_t n = static_cast<std::size_t>(model.nbodies());
    std::vector<int> root(n), end(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      root[i] = model.parent[i] < 0 ? static_cast<int>(i) : root[static_cast<std::size_t>(model.parent[i])];
    std::vector<int> first(n, cases);
    for (const LoopTpl<S>& loop : model.loops)
      for (const int body : {loop.body_a, loop.body_b}) {
        if (body < 0) continue;
        const std::size_t r = static_cast<std::size_t>(root[static_cast<std::size_t>(body)]);
        first[r] = std::min(first[r], loop.first_row);
        end[r] = std::max(end[r], loop.first_row + loop.rows());
      }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t r = static_cast<std::size_t>(root[i]);
      first_case[i] = first[r] < end[r] ? first[r] : 0;
      case_count[i] = first[r] < end[r] ? end[r] - first[r] : 0;
    }
  }
  int cases;
  Mat6X<S> z, alpha;
  MatX<S> eps, qdd;
  std::vector<int> first_case, case_count;  // per body: its tree's load cases
  // Body i's columns of z and alpha, and the load cases' columns of eps and
  // qdd, over its tree's cases.
  auto z_of(std::size_t body) {
    return z.middleCols(static_cast<Eigen::Index>(body) * cases + first_case[body], case_count[body]);
  }
  auto alpha_of(std::size_t body) {
    return alpha.middleCols(static_cast<Eigen::Index>(body) * cases + first_case[body], case_count[body]);
  }
  auto eps_of(std::size_t body) { return eps.middleCols(first_case[body], case_count[body]); }
  auto qdd_of(std::size_t body) { return qdd.middleCols(first_case[body], case_count[body]); }
};

template <class S>
struct LoopData {
  explicit LoopData(const ModelTpl<S>& model)
      : LoopData(model, model.nq, model.nv, model.nloop_equations, model.nloops(), model.nbodies()) {}

 private:
  LoopData(const ModelTpl<S>& model, int nq, int nv, int m, int nloops, int nbodies)
      : residual(VecX<S>::Zero(m)), velocity_residual(VecX<S>::Zero(m)), jacobian(MatX<S>::Zero(m, nv)),
        kappa(VecX<S>::Zero(m)), multipliers(VecX<S>::Zero(m)), wrench(static_cast<std::size_t>(nloops), Vec6<S>::Zero()),
        directions(static_cast<std::size_t>(nloops), Mat6<S>::Zero()),
        point_a(static_cast<std::size_t>(nloops), Vec3<S>::Zero()), point_p(static_cast<std::size_t>(nloops), Vec3<S>::Zero()),
        relative_jacobian(Mat6X<S>::Zero(6, nv)), regular_mass(MatX<S>::Zero(nv, nv)),
        constraint_jacobian_regular(MatX<S>::Zero(m, nv)), regular_jacobian_transposed(MatX<S>::Zero(nv, m)),
        half_solved_ct(MatX<S>::Zero(nv, m)),
        delassus(MatX<S>::Zero(m, m)), delassus_solve(m), rhs(VecX<S>::Zero(m)), equation_scale(VecX<S>::Zero(m)),
        closure_acceleration_error(VecX<S>::Zero(m)),
        free_acceleration(VecX<S>::Zero(nv)), bias(VecX<S>::Zero(nv)), null_basis(MatX<S>::Zero(m, m)),
        null_work(VecX<S>::Zero(m)), actuation_map(MatX<S>::Zero(nv, m)), actuation_gram(MatX<S>::Zero(m, m)),
        actuation_solve(m), actuation_rhs(VecX<S>::Zero(m)), actuation_step(VecX<S>::Zero(m)),
        rank_qr(m, nv),
        projection_multipliers(VecX<S>::Zero(m)), correction(VecX<S>::Zero(nv)), q_start(VecX<S>::Zero(nq)),
        tree_origin(static_cast<std::size_t>(nbodies), Vec3<S>::Zero()), on_loop_path(static_cast<std::size_t>(nbodies), 0),
        unit_response(model) {}

 public:

  // Outputs.
  VecX<S> residual;           // Psi(q), m
  VecX<S> velocity_residual;  // C v, m
  MatX<S> jacobian;           // C (m x nv): C v is the relative velocity of the cut joints
  VecX<S> kappa;              // C qdd = kappa, kappa = -Cdot v
  VecX<S> multipliers;        // lambda: M qdd + h = tau + C' lambda
  aligned_vector<Vec6<S>> wrench;  // per loop: [torque; force] of B's side on A's side, world axes, about A's origin
  aligned_vector<Mat6<S>> directions;  // per loop: W (loop_closure.hxx), its first rows() columns: wrench = W lambda
  // Per loop, world positions: frame A's origin, and the point P of body B
  // whose velocity C compares (B's origin; A's for a prismatic loop).
  aligned_vector<Vec3<S>> point_a, point_p;

  // Scratch.
  Mat6X<S> relative_jacobian;              // [omega_A - omega_B; v_A - v_B(P)] as a 6 x nv map of v
  MatX<S> regular_mass;                    // M with the prescribed rows and columns replaced by the identity,
                                           // then its tree-sparse factor, M_rr = L' L (U = L' in the upper triangle)
  MatX<S> constraint_jacobian_regular;     // C with the fixed columns zeroed (loop assembly)
  MatX<S> regular_jacobian_transposed;     // its transpose (the articulated-body solve)
  MatX<S> half_solved_ct;                  // Y = L'^-1 C_r' with M_rr = L' L (tree_cholesky.hpp)
  MatX<S> delassus;                        // C_r M_rr^-1 C_r' (m x m)
  SemidefiniteSolveScratch<S> delassus_solve;  // minimum-norm multipliers (semidefinite_solve.hpp)
  VecX<S> rhs;
  VecX<S> equation_scale;                  // per closure equation, the size of its terms (inconsistent_loop)
  VecX<S> closure_acceleration_error;      // C qdd - kappa (inconsistent_loop)
  VecX<S> free_acceleration;               // qdd without loop forces
  VecX<S> bias;                            // h - J' f_ext
  // Minimum-norm actuator forces (constrained_dynamics.hpp, redundant actuation):
  MatX<S> null_basis;                      // N: m x (m - rank) basis of the null space of the Delassus matrix
  VecX<S> null_work;
  MatX<S> actuation_map;                   // B = C_p' N (nv x (m - rank)): prescribed forces along N
  MatX<S> actuation_gram;                  // B'B, zero-padded to m x m
  SemidefiniteSolveScratch<S> actuation_solve;
  VecX<S> actuation_rhs, actuation_step;   // B' tau0 and z (lambda = lambda0 + N z)
  Eigen::ColPivHouseholderQR<MatX<S>> rank_qr;
  // Closure projection (loop_assembly.hpp): its multipliers, the tangent
  // correction of q or v, and the configuration a Gauss-Newton step starts from.
  VecX<S> projection_multipliers, correction, q_start;
  // The articulated-body solve (articulated_loop_response.hxx), tree frames:
  // per body, the world position of its tree's origin, and whether it lies
  // on a loop body's root path (loaded).
  aligned_vector<Vec3<S>> tree_origin;
  std::vector<std::uint8_t> on_loop_path;
  // The responses to each unit multiplier (one column per loop equation) on
  // the loaded bodies.
  ArticulatedResponse<S> unit_response;
};

}  // namespace soadyn
