// The packet path's mass matrix (algorithms/packet_kernels.hpp): the
// composite-rigid-body algorithm compiled for AVX2 without fused
// multiply-adds, so that each lane rounds as the baseline double kernel
// does (crba.cpp). The AVX2 FMA kernel the single call runs on such
// processors rounds its fused products once: its M differs in the last bits.
#include "soadyn/algorithms/packet_kernels.hpp"

#include "soadyn/algorithms/crba.hxx"

namespace soadyn::detail {

Status packet_mass_matrix(const PacketModel& m, PacketData& d, const PacketVector& q) {
  return mass_matrix<Packet4d>(m, d, q);
}

}  // namespace soadyn::detail
