#include "soadyn/algorithms/frames.hxx"

namespace soadyn {
#define SOADYN_INSTANTIATE(S)                                                                                      \
  template FrameLocation<S> locate_frame<S>(const ModelTpl<S>&, const std::string&);                              \
  template FrameLocation<S> locate_frame<S>(const ModelTpl<S>&, int);                                             \
  template Transform<S> frame_pose<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,                     \
                                      const FrameLocation<S>&);                                                   \
  template Vec6<S> frame_velocity<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const ConstVecRef<S>&, \
                                     const FrameLocation<S>&, Reference);                                         \
  template Vec6<S> frame_acceleration<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,                  \
                                         const ConstVecRef<S>&, const ConstVecRef<S>&, const FrameLocation<S>&,  \
                                         Reference, bool);                                                        \
  template void frame_jacobian<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&, const FrameLocation<S>&, \
                                  Reference, Mat6XRef<S>);                                                        \
  template void frame_jacobian_time_variation<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,          \
                                                 const ConstVecRef<S>&, const FrameLocation<S>&, Reference,       \
                                                 Mat6XRef<S>);                                                    \
  template bool center_of_mass_jacobian<S>(const ModelTpl<S>&, DataTpl<S>&, const ConstVecRef<S>&,                \
                                           SubtreeMassWorkspace<S>&, Mat3XRef<S>);
SOADYN_INSTANTIATE(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE(float)
#endif
}  // namespace soadyn
