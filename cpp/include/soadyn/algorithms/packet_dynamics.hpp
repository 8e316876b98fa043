// Four states per pass: the forward, inverse and hybrid dynamics and the
// mass matrix of four rows of a batch (parallel/batch_dynamics.hpp) at once,
// the algorithms run on packets of four doubles (core/packet.hpp), one state
// per lane, compiled for AVX2 (one instruction for the four lanes).
//
// Each lane's forward, inverse and hybrid dynamics are the single call's,
// bit for bit: the packet operations are the double ones lane by lane, the
// joint angles' sines and cosines come from the same kernel, Eigen sums
// products over packets in the order it sums doubles (core/packet.hpp), and
// nothing is fused into multiply-adds, as in the single call. The mass
// matrix is the baseline kernel's bit for bit; on processors with AVX2 and
// FMA the single call runs its FMA kernel, whose M differs in the last bits
// (algorithms/crba.hpp). When the four states take different branches (a
// comparison on values whose lanes disagree) or a lane fails, the four rows
// are computed again one by one by the single call, so each row's result
// and status are exactly the single call's.
//
// Flexible bodies too: the appendages' update, which the single call runs
// with a double kernel of its own, runs that kernel lane by lane
// (sweeps/packet_appendage_update.hpp), so those lanes are the single
// call's bit for bit as well; a flexible model's mass matrix has no kernel
// of its own and is the single call's.
#pragma once
#include <array>
#include <memory>

#include "soadyn/model/data.hpp"
#include "soadyn/core/status.hpp"
#include "soadyn/core/packet.hpp"
#include "soadyn/sweeps/packet_appendage_update.hpp"

namespace soadyn {

// The model in packets (every value in all four lanes), shared by the
// PacketDynamics of all threads.
class PacketModel {
 public:
  explicit PacketModel(const Model& model);
  // Four models of one structure that differ in their parameters' values
  // (model/parameters.hpp: a rollout's runs, each with its own), lane l
  // holding models[l]'s values. Null when the four cannot share one packet
  // model: their structure or flags differ, or a property the model derives
  // from its values differs between them (whether a placement's rotation
  // permutes the axes, whether an inertia is diagonal or symmetric about a
  // joint axis, whether a body's tree-frame reach is checked). Allocates.
  static std::unique_ptr<PacketModel> of_lanes(const std::array<const Model*, 4>& models);
  ~PacketModel();
  // Takes the model's values again (masses, prescribed flags, gravity, ...:
  // whatever changed short of its structure; Model::cast_values_into).
  // Allocation free.
  void refresh(const Model& model);
  const ModelTpl<Packet4d>& get() const { return *model_; }

 private:
  PacketModel();
  std::unique_ptr<ModelTpl<Packet4d>> model_;
};

class PacketDynamics {
 public:
  static constexpr int lanes = 4;

  // Whether the packet path serves `model`: every model, rigid or flexible
  // (rollouts keep models with closed loops one run per pass, rollout.cpp).
  static bool serves(const Model& model);
  // Whether this processor runs the packet path: AVX2 and FMA, and the
  // baseline kernels not requested (processor_features.hpp).
  static bool available();

  // `model` and `packets` (its PacketModel) must outlive this object, and
  // the model keep its structure; serves(model).
  PacketDynamics(const Model& model, const PacketModel& packets);
  ~PacketDynamics();
  PacketDynamics(const PacketDynamics&) = delete;
  PacketDynamics& operator=(const PacketDynamics&) = delete;

  // Four consecutive rows of row-major arrays laid out as BatchDynamics's
  // (Q 4 x nq, V and the rest 4 x nv, F null or 4 x nbodies x 6); status
  // receives the four rows' statuses. Allocation free.
  void forward_dynamics(const double* Q, const double* V, const double* TAU, const double* F, double* QDD,
                        Status* status);
  void inverse_dynamics(const double* Q, const double* V, const double* QDD, const double* F, double* TAU,
                        Status* status);
  void hybrid_dynamics(const double* Q, const double* V, const double* U, const double* F, double* QDD, double* TAU,
                       Status* status);
  void mass_matrix(const double* Q, double* M, Status* status);

 private:
  struct Packets;
  // Loads the rows' states into the packets (V, X, F may be null).
  void load(const double* Q, const double* V, const double* X, const double* F);
  // After a packet call: whether its lanes stand (status ok, no split
  // branch), and if so each row's status.
  bool packet_stands(const Status& packet_status, Status* status);
  // store() the lanes if the packet stands, else status[l] = row(l): the
  // single call on row l, its outputs stored.
  template <class Store, class Row>
  void finish(const Status& packet_status, Status* status, Store&& store, Row&& row);
  // Row `lane`'s wrenches in F (null: none).
  const double* wrenches(const double* F, int lane) const;

  const Model& model_;
  const PacketModel& packet_model_;
  std::unique_ptr<Packets> packets_;
  Data scalar_;  // the rows computed again one by one, and the appendages' lanes (PacketLanes)
  PacketLanes lanes_;
};

}  // namespace soadyn
