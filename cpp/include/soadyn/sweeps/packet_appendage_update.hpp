// The flexible appendages' update (appendage_update.hpp) on packets of four
// states, lane by lane with the double kernel the single call runs, so that
// each lane's P^, z^ and modal terms are the single call's bit for bit
// whichever kernel this processor chose (the AVX2 FMA one fuses products
// that no packet code fuses alike). The packet path names each lane's
// double model, and lends a double Data to work in, for the packet calls it
// makes on its thread (PacketLanesScope). Without them the update marks the
// packet as split (core/packet.hpp), and the caller computes its rows one by
// one.
#pragma once
#include <array>

#include "soadyn/model/data.hpp"

namespace soadyn {

// Each lane's model (lane l's values: the same structure in all four) and a
// double workspace of that structure. Built before the calls: allocates.
struct PacketLanes {
  PacketLanes(const std::array<const Model*, 4>& models, Data& scratch);
  std::array<const Model*, 4> models;
  Data& scratch;
  Eigen::VectorXd q, v, u;  // one lane's coordinates, velocities and inputs
};

// Names `lanes` to the packet appendage updates of this thread while it lives.
class PacketLanesScope {
 public:
  explicit PacketLanesScope(PacketLanes& lanes);
  ~PacketLanesScope();
  PacketLanesScope(const PacketLanesScope&) = delete;
  PacketLanesScope& operator=(const PacketLanesScope&) = delete;

 private:
  PacketLanes* previous_;
};

namespace detail {
// appendage_update on packets (appendage_update.hpp calls it); allocation free.
void packet_appendage_update(const ModelTpl<Packet4d>& m, DataTpl<Packet4d>& d, std::size_t i,
                             const ModalIntegrals<Packet4d>& mi, const Packet4d* q, const Packet4d* v,
                             const Packet4d* u, const Vec6<Packet4d>* external, const Vec6<Packet4d>& V,
                             Mat6<Packet4d>& P, Vec6<Packet4d>& z);
}  // namespace detail

}  // namespace soadyn
