// Four states per pass (algorithms/packet_dynamics.hpp): the rows' states
// into packets, the packet algorithm, the lanes out; the rows one by one
// when the packet does not stand.
#include "soadyn/algorithms/packet_dynamics.hpp"

#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/algorithms/packet_kernels.hpp"
#include "soadyn/algorithms/rnea.hpp"
#include "soadyn/core/processor_features.hpp"
#include "soadyn/flex/cantilever_beam.hxx"
#include "soadyn/flex/flexible_body.hxx"
#include "soadyn/flex/modal_integrals.hxx"
#include "soadyn/model/data.hxx"
#include "soadyn/model/model.hxx"
#include "soadyn/model/model_cast.hxx"

namespace soadyn {

// Compiled for AVX2 in packet_kernels.cpp and packet_step.cpp, whose code
// calls them: a copy instantiated here, for the baseline, could be the one
// the linker keeps (tests/cpp/check_packet_objects.py).
extern template Mat3<Packet4d> quaternion_rotation<Packet4d>(const Packet4d*);
extern template void ModelTpl<Packet4d>::refresh_leaf_presums();

// The packet model and its Data (the flexible bodies' types come with them,
// unused: PacketDynamics serves rigid trees).
template ModelTpl<Packet4d> ModelTpl<double>::cast<Packet4d>() const;
template bool ModelTpl<double>::cast_into<Packet4d, PacketDynamics::lanes>(
    const std::array<const ModelTpl<double>*, PacketDynamics::lanes>&, ModelTpl<Packet4d>&);
template bool ModelTpl<double>::cast_values_into<Packet4d, 1>(const std::array<const ModelTpl<double>*, 1>&,
                                                              ModelTpl<Packet4d>&);
template struct DataTpl<Packet4d>;
template Transform<Packet4d> FlexibleBodyTpl<Packet4d>::node_motion(int, const Eigen::Ref<const VecX<Packet4d>>&,
                                                                   Eigen::Ref<ModeShape<Packet4d>>, const Packet4d*,
                                                                   Vec6<Packet4d>*) const;
template struct ModalIntegrals<Packet4d>;
template void ModalIntegrals<Packet4d>::second_moment_rates<Eigen::Dynamic>(const Eigen::Ref<const VecX<Packet4d>>&,
                                                                              MatX<Packet4d>&) const;
template void ModalIntegrals<Packet4d>::inertial_bias<Eigen::Dynamic>(const Eigen::Ref<const VecX<Packet4d>>&,
                                                                        const Vec6<Packet4d>&, const Vec6<Packet4d>&,
                                                                        const MatX<Packet4d>&,
                                                                        Eigen::Ref<VecX<Packet4d>>) const;

namespace {

using Map = Eigen::Map<const Eigen::VectorXd>;
using VectorOut = Eigen::Map<Eigen::VectorXd>;
constexpr int kLanes = PacketDynamics::lanes;

// Lane l of packets x (n of them) into out[l * n + k].
void store_lanes(const Packet4d* x, Eigen::Index n, double* out) {
  for (int l = 0; l < kLanes; ++l)
    for (Eigen::Index k = 0; k < n; ++k) out[l * n + k] = x[k][l];
}

// Row `lane` of a row-major array of rows of `width` values.
Map row(const double* rows, int lane, int width) { return Map(rows + static_cast<std::ptrdiff_t>(lane) * width, width); }

// rows[l * n + k] of the four rows into packet k's lane l: each packet
// formed whole and stored once, not lane by lane.
void load_lanes(const double* rows, Eigen::Index n, Packet4d* x) {
  const double *r0 = rows, *r1 = rows + n, *r2 = rows + 2 * n, *r3 = rows + 3 * n;
  for (Eigen::Index k = 0; k < n; ++k) x[k] = Packet4d(Packet4d::Lanes{r0[k], r1[k], r2[k], r3[k]});
}

}  // namespace

PacketModel::PacketModel(const Model& model) : model_(std::make_unique<ModelTpl<Packet4d>>(model.cast<Packet4d>())) {}

PacketModel::PacketModel() : model_(std::make_unique<ModelTpl<Packet4d>>()) {}

std::unique_ptr<PacketModel> PacketModel::of_lanes(const std::array<const Model*, kLanes>& models) {
  std::unique_ptr<PacketModel> out(new PacketModel());
  clear_lane_divergence();  // the derived properties' comparisons record a split (core/packet.hpp)
  const bool agree = Model::cast_into<Packet4d, kLanes>(models, *out->model_);
  if (!agree || lanes_diverged()) return nullptr;
  return out;
}

PacketModel::~PacketModel() = default;

void PacketModel::refresh(const Model& model) { Model::cast_values_into<Packet4d, 1>({&model}, *model_); }

struct PacketDynamics::Packets {
  explicit Packets(const detail::PacketModel& model)
      : data(model), q(model.nq), v(model.nv), x(model.nv), f(static_cast<std::size_t>(6 * model.nbodies())) {}
  detail::PacketData data;
  detail::PacketVector q, v, x;
  aligned_vector<Packet4d> f;  // on a cache line (spatial/types.hpp)
};

bool PacketDynamics::serves(const Model&) { return true; }

bool PacketDynamics::available() { return avx2_fma_kernels_enabled(); }

PacketDynamics::PacketDynamics(const Model& model, const PacketModel& packet_model)
    : model_(model), packet_model_(packet_model), packets_(std::make_unique<Packets>(packet_model.get())),
      scalar_(model), lanes_({&model, &model, &model, &model}, scalar_) {}

PacketDynamics::~PacketDynamics() = default;

void PacketDynamics::load(const double* Q, const double* V, const double* X, const double* F) {
  Packets& p = *packets_;
  load_lanes(Q, model_.nq, p.q.data());
  if (V) load_lanes(V, model_.nv, p.v.data());
  if (X) load_lanes(X, model_.nv, p.x.data());
  if (F) load_lanes(F, 6 * model_.nbodies(), p.f.data());
  clear_lane_divergence();
}

bool PacketDynamics::packet_stands(const Status& packet_status, Status* status) {
  if (!packet_status.ok() || lanes_diverged()) return false;
  for (int l = 0; l < kLanes; ++l) status[l] = packet_status;
  return true;
}

template <class Store, class Row>
void PacketDynamics::finish(const Status& packet_status, Status* status, Store&& store, Row&& row) {
  if (packet_stands(packet_status, status)) return store();
  for (int l = 0; l < kLanes; ++l) status[l] = row(l);
}

void PacketDynamics::forward_dynamics(const double* Q, const double* V, const double* TAU, const double* F,
                                      double* QDD, Status* status) {
  Packets& p = *packets_;
  load(Q, V, TAU, F);
  const int nv = model_.nv;
  const PacketLanesScope lanes_in_use(lanes_);
  finish(detail::packet_forward_dynamics(packet_model_.get(), p.data, p.q, p.v, p.x, F ? p.f.data() : nullptr), status,
         [&] { store_lanes(p.data.qdd.data(), nv, QDD); },
         [&](int l) {
           const Status s = soadyn::forward_dynamics<double>(model_, scalar_, row(Q, l, model_.nq), row(V, l, nv),
                                                             row(TAU, l, nv), wrenches(F, l));
           VectorOut(QDD + l * nv, nv) = scalar_.qdd;
           return s;
         });
}

void PacketDynamics::inverse_dynamics(const double* Q, const double* V, const double* QDD, const double* F,
                                      double* TAU, Status* status) {
  Packets& p = *packets_;
  load(Q, V, QDD, F);
  const int nv = model_.nv;
  finish(detail::packet_inverse_dynamics(packet_model_.get(), p.data, p.q, p.v, p.x, F ? p.f.data() : nullptr), status,
         [&] { store_lanes(p.data.tau.data(), nv, TAU); },
         [&](int l) {
           const Status s = soadyn::inverse_dynamics<double>(model_, scalar_, row(Q, l, model_.nq), row(V, l, nv),
                                                             row(QDD, l, nv), wrenches(F, l));
           VectorOut(TAU + l * nv, nv) = scalar_.tau;
           return s;
         });
}

void PacketDynamics::hybrid_dynamics(const double* Q, const double* V, const double* U, const double* F, double* QDD,
                                     double* TAU, Status* status) {
  Packets& p = *packets_;
  load(Q, V, U, F);
  const int nv = model_.nv;
  const PacketLanesScope lanes_in_use(lanes_);
  finish(detail::packet_hybrid_dynamics(packet_model_.get(), p.data, p.q, p.v, p.x, F ? p.f.data() : nullptr), status,
         [&] {
           store_lanes(p.data.qdd.data(), nv, QDD);
           store_lanes(p.data.tau.data(), nv, TAU);
         },
         [&](int l) {
           const Status s = soadyn::hybrid_dynamics<double>(model_, scalar_, row(Q, l, model_.nq), row(V, l, nv),
                                                            row(U, l, nv), wrenches(F, l), DynamicsOutputs{false});
           VectorOut(QDD + l * nv, nv) = scalar_.qdd;
           VectorOut(TAU + l * nv, nv) = scalar_.tau;
           return s;
         });
}

void PacketDynamics::mass_matrix(const double* Q, double* M, Status* status) {
  Packets& p = *packets_;
  load(Q, nullptr, nullptr, nullptr);
  const int nv = model_.nv;
  finish(detail::packet_mass_matrix(packet_model_.get(), p.data, p.q), status,
         // M is symmetric: its column-major packets are the row-major rows.
         [&] { store_lanes(p.data.mass_matrix.data(), static_cast<Eigen::Index>(nv) * nv, M); },
         [&](int l) {
           const Status s = soadyn::mass_matrix<double>(model_, scalar_, row(Q, l, model_.nq));
           copy_mass_matrix_rows(scalar_.mass_matrix, M + static_cast<Eigen::Index>(l) * nv * nv);
           return s;
         });
}

const double* PacketDynamics::wrenches(const double* F, int lane) const {
  return F ? F + static_cast<std::ptrdiff_t>(lane) * 6 * model_.nbodies() : nullptr;
}

}  // namespace soadyn
