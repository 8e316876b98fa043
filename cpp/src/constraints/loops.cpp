#include "soadyn/constraints/constrained_dynamics.hxx"
#include "soadyn/constraints/constrained_impulse.hxx"
#include "soadyn/constraints/loop_assembly.hxx"
#include "soadyn/constraints/loop_closure.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                  \
  template void loop_residual<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const S*);            \
  template int loop_rank<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&);                          \
  template Status constrained_dynamics<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,              \
                                          const ConstVecRef<S>&, const ConstVecRef<S>&, const S*, DynamicsOutputs); \
  template Status loop_joint_wrenches<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,               \
                                         const ConstVecRef<S>&, const ConstVecRef<S>&, const S*, const S*);   \
  template Status detail::constrained_solve<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&);      \
  template Status assemble_loops<S>(const ModelTpl<S>&, DataTpl<S>&, VecRef<S>, const ConstVecRef<S>&, S, int,  \
                                    int*, const Interrupt*);                                                                   \
  template Status project_loop_velocity<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, VecRef<S>,   \
                                           const ConstVecRef<S>&);                                              \
  template std::vector<int> independent_coordinates<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&); \
  template Status constrained_impulse<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,                \
                                         const ConstVecRef<S>&, const ConstVecRef<S>&);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
