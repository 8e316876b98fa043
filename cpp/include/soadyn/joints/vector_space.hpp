// The configuration space of joints whose coordinates are their velocities'
// integrals (q' = v, nq = nv = N): revolute, prismatic, helical, universal,
// cylindrical, translation, fixed (N = 0). Every operation is the vector-space
// one; the chart around q0 is q = q0 + xi with dxi/dt = v (sim/chart.hpp).
// Curved spaces (planar.hpp, spherical.hpp, free.hpp) provide the same
// members.
#pragma once
#include "soadyn/spatial/types.hpp"

namespace soadyn {

template <class S, int N>
struct VectorSpace {
  static constexpr int nq = N, nv = N;
  static constexpr int quaternion_offset = -1;  // offset of a unit quaternion in q, or -1
  static constexpr bool scalar_coordinates = true;  // q' = v: a motion source may set q directly

  static void neutral(S* q) {
    for (int k = 0; k < N; ++k) q[k] = S(0);
  }
  // q_out = q (+) v dt (may alias q).
  static void integrate(const S* q, const S* v, const S& dt, S* q_out) {
    for (int k = 0; k < N; ++k) q_out[k] = q[k] + v[k] * dt;
  }
  // q = retract(q0, xi).
  static void retract(const S* q0, const S* xi, S* q) {
    for (int k = 0; k < N; ++k) q[k] = q0[k] + xi[k];
  }
  // dxi/dt at q = retract(q0, xi) for velocity v.
  static void chart_rate(const S*, const S*, const S* v, S* rate) {
    for (int k = 0; k < N; ++k) rate[k] = v[k];
  }
  // First-order maps of the chart (analysis/linearization.hpp), written into the
  // joint's N x N diagonal block at (o, o) of nv x nv matrices; q =
  // retract(q0, xi). Tangent directions are those of integrate.
  //   base_transport   d(tangent at q) / d(tangent at q0), xi fixed
  //   chart_transport  d(tangent at q) / d xi
  //   rate_jacobians   d chart_rate / d(tangent at q0), / d xi, / d v
  //   bracket          ad_v: ad_v e = [v, e], the Lie bracket of the joint's group
  static void base_transport(const S*, const S*, const S*, MatX<S>& T, int o) {
    T.block(o, o, N, N).setIdentity();
  }
  static void chart_transport(const S*, const S*, const S*, MatX<S>& T, int o) {
    T.block(o, o, N, N).setIdentity();
  }
  static void rate_jacobians(const S*, const S*, const S*, const S*, MatX<S>&, MatX<S>&, MatX<S>& d_v, int o) {
    d_v.block(o, o, N, N).setIdentity();
  }
  static void bracket(const S*, MatX<S>&, int) {}
};

}  // namespace soadyn
