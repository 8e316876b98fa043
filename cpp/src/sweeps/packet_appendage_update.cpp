// The appendages' update on packets, lane by lane (packet_appendage_update.hpp).
#include "soadyn/sweeps/packet_appendage_update.hpp"

#include "soadyn/core/packet.hpp"
#include "soadyn/sweeps/appendage_update.hpp"

namespace soadyn {

namespace {

constexpr int kLanes = Packet4d::lanes;

thread_local PacketLanes* current_lanes = nullptr;

// Lane l of n packets into n doubles, and back.
void take_lane(const Packet4d* from, Eigen::Index n, int l, double* to) {
  for (Eigen::Index k = 0; k < n; ++k) to[k] = from[k][l];
}
void put_lane(const double* from, Eigen::Index n, int l, Packet4d* to) {
  for (Eigen::Index k = 0; k < n; ++k) to[k][l] = from[k];
}
template <class Doubles, class Packets>
void put_lane(const Doubles& from, int l, Packets& to) {
  put_lane(from.data(), from.size(), l, to.data());
}

// The double integrals that `mi` holds in packets: the model's own ones of
// the appendage's flexible body, or those in its root's frame (the two the
// sweeps pass, tree_frame_updates.hpp).
const ModalIntegrals<double>& lane_integrals(const ModelTpl<Packet4d>& m, const Model& lane_model, std::size_t i,
                                             const ModalIntegrals<Packet4d>& mi) {
  const std::size_t f = static_cast<std::size_t>(m.flexible_index[i]);
  if (f < m.derived.root_frame_integrals.size() && &mi == &m.derived.root_frame_integrals[f])
    return lane_model.derived.root_frame_integrals[f];
  return lane_model.flexible_body(static_cast<int>(i)).modal_integrals();
}

}  // namespace

PacketLanes::PacketLanes(const std::array<const Model*, 4>& lane_models, Data& workspace)
    : models(lane_models), scratch(workspace), q(lane_models[0]->nq), v(lane_models[0]->nv), u(lane_models[0]->nv) {}

PacketLanesScope::PacketLanesScope(PacketLanes& lanes) : previous_(current_lanes) { current_lanes = &lanes; }

PacketLanesScope::~PacketLanesScope() { current_lanes = previous_; }

namespace detail {

void packet_appendage_update(const ModelTpl<Packet4d>& m, DataTpl<Packet4d>& d, std::size_t i,
                             const ModalIntegrals<Packet4d>& mi, const Packet4d* q, const Packet4d* v,
                             const Packet4d* u, const Vec6<Packet4d>* external, const Vec6<Packet4d>& V,
                             Mat6<Packet4d>& P, Vec6<Packet4d>& z) {
  PacketLanes* lanes = current_lanes;
  if (!lanes) {  // no double models to run: the caller computes the rows one by one
    packet_detail::diverged = true;
    P.setZero();  // defined values for the rest of the abandoned sweep
    z.setZero();
    return;
  }
  Data& w = lanes->scratch;
  FlexibleBodyData<Packet4d>& packet_body = flexible_data(m, d, i);
  const FlexibleBodyData<double>& lane_body = flexible_data(*lanes->models[0], w, i);
  const int body = static_cast<int>(i), first_q = m.modal_q_index(body), first_v = m.modal_v_index(body),
            modes = m.n_modes[i];
  for (int l = 0; l < kLanes; ++l) {
    const Model& lane_model = *lanes->models[static_cast<std::size_t>(l)];
    // The update reads the appendage's own modal coordinates, rates and
    // forces only: those entries of the lane's arrays.
    take_lane(q + first_q, modes, l, lanes->q.data() + first_q);
    if (v) take_lane(v + first_v, modes, l, lanes->v.data() + first_v);
    if (u) take_lane(u + first_v, modes, l, lanes->u.data() + first_v);
    Vec6<double> lane_external, lane_V, z_lane;
    Mat6<double> P_lane;
    if (external) take_lane(external->data(), 6, l, lane_external.data());
    take_lane(V.data(), 6, l, lane_V.data());
    // The single call's kernel, as the double sweep calls it (appendage_update.hpp).
    compiled_appendage_update(lane_model, w, i, lane_integrals(m, lane_model, i, mi), lanes->q.data(),
                              v ? lanes->v.data() : nullptr, u ? lanes->u.data() : nullptr,
                              external ? &lane_external : nullptr, lane_V, P_lane, z_lane);
    put_lane(P_lane, l, P);
    put_lane(z_lane, l, z);
    put_lane(w.sweep.body_bias_force[i], l, d.sweep.body_bias_force[i]);
    put_lane(lane_body.second_moment_rates, l, packet_body.second_moment_rates);
    put_lane(lane_body.bias, l, packet_body.bias);
    put_lane(lane_body.modal_bias, l, packet_body.modal_bias);
    put_lane(lane_body.deformed_angular_coupling, l, packet_body.deformed_angular_coupling);
    put_lane(lane_body.gain_transpose, l, packet_body.gain_transpose);
    put_lane(lane_body.innovation, l, packet_body.innovation);
  }
}

}  // namespace detail

}  // namespace soadyn
