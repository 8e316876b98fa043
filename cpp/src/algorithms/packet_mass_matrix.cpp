// The packet path's mass matrix (algorithms/packet_kernels.hpp): the
// composite-rigid-body algorithm compiled for AVX2 with fused multiply-adds,
// as the double call's AVX2 FMA kernel is (crba.cpp), so that each lane
// rounds as that kernel does.
#include "soadyn/algorithms/packet_kernels.hpp"

#include "soadyn/algorithms/crba.hxx"

namespace soadyn::detail {

Status packet_mass_matrix(const PacketModel& m, PacketData& d, const PacketVector& q) {
  return mass_matrix<Packet4d>(m, d, q);
}

}  // namespace soadyn::detail
