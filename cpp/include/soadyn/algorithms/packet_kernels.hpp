// The packet path's algorithms (algorithms/packet_dynamics.hpp): the
// library's templates instantiated on Packet4d, each compiled for AVX2 with
// every call inlined into it (packet_kernels.cpp, packet_mass_matrix.cpp).
// Call them only where PacketDynamics::available().
#pragma once
#include "soadyn/core/packet.hpp"
#include "soadyn/core/status.hpp"
#include "soadyn/model/data.hpp"

namespace soadyn::detail {

using PacketModel = ModelTpl<Packet4d>;
using PacketData = DataTpl<Packet4d>;
using PacketVector = VecX<Packet4d>;

Status packet_forward_dynamics(const PacketModel& m, PacketData& d, const PacketVector& q, const PacketVector& v,
                               const PacketVector& tau, const Packet4d* f_ext);
Status packet_inverse_dynamics(const PacketModel& m, PacketData& d, const PacketVector& q, const PacketVector& v,
                               const PacketVector& qdd, const Packet4d* f_ext);
Status packet_hybrid_dynamics(const PacketModel& m, PacketData& d, const PacketVector& q, const PacketVector& v,
                              const PacketVector& u, const Packet4d* f_ext);
Status packet_mass_matrix(const PacketModel& m, PacketData& d, const PacketVector& q);

}  // namespace soadyn::detail
