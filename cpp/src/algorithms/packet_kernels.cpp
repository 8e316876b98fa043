// The packet path's forward, inverse and hybrid dynamics
// (algorithms/packet_kernels.hpp). Compiled for AVX2 without contracting
// products into fused multiply-adds (CMakeLists.txt), as the single calls'
// double code is compiled: each lane rounds exactly as they do.
#include "soadyn/algorithms/packet_kernels.hpp"

#include "soadyn/algorithms/aba.hxx"
#include "soadyn/algorithms/hybrid.hxx"
#include "soadyn/algorithms/rnea.hxx"

namespace soadyn::detail {

Status packet_forward_dynamics(const PacketModel& m, PacketData& d, const PacketVector& q,
                                                    const PacketVector& v, const PacketVector& tau,
                                                    const Packet4d* f_ext) {
  return forward_dynamics<Packet4d>(m, d, q, v, tau, f_ext);
}

Status packet_inverse_dynamics(const PacketModel& m, PacketData& d, const PacketVector& q,
                                                    const PacketVector& v, const PacketVector& qdd,
                                                    const Packet4d* f_ext) {
  return inverse_dynamics<Packet4d>(m, d, q, v, qdd, f_ext);
}

Status packet_hybrid_dynamics(const PacketModel& m, PacketData& d, const PacketVector& q,
                                                   const PacketVector& v, const PacketVector& u,
                                                   const Packet4d* f_ext) {
  return hybrid_dynamics<Packet4d>(m, d, q, v, u, f_ext, DynamicsOutputs{false});
}

}  // namespace soadyn::detail

namespace soadyn {
// For packet_dynamics.cpp (the model's cast), compiled for the baseline.
template Mat3<Packet4d> quaternion_rotation<Packet4d>(const Packet4d*);
}  // namespace soadyn
