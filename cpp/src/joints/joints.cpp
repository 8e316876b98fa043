// Every operation on every joint type (joints/joint_types.hpp), compiled
// once for double and float: a joint type that does not build for a scalar
// fails here, not in a user's program.
#include "soadyn/joints/joint.hpp"

namespace soadyn {

#define SOADYN_INSTANTIATE_JOINTS(S)                                                                          \
  template int joint_nq<S>(const JointModel<S>&);                                                             \
  template int joint_nv<S>(const JointModel<S>&);                                                             \
  template const char* joint_type_name<S>(const JointModel<S>&);                                              \
  template const char* const* joint_coordinate_suffixes<S>(const JointModel<S>&);                             \
  template const char* const* joint_velocity_suffixes<S>(const JointModel<S>&);                               \
  template int joint_quaternion_offset<S>(const JointModel<S>&);                                              \
  template bool joint_translates<S>(const JointModel<S>&);                                                    \
  template void check_joint<S>(JointModel<S>&, const std::string&);                                           \
  template JointFastPath classify_joint<S>(const JointModel<S>&, S&);                                           \
  template void joint_calc<S>(const JointModel<S>&, const S*, const S*, Transform<S>&, Mat6N<S>&, Vec6<S>&);  \
  template void joint_init_subspace<S>(const JointModel<S>&, Mat6N<S>&);                                      \
  template void joint_neutral<S>(const JointModel<S>&, S*);                                                   \
  template void joint_random<S>(const JointModel<S>&, CoordinateSampler&, S*);                                \
  template void joint_integrate<S>(const JointModel<S>&, const S*, const S*, const S&, S*);
SOADYN_INSTANTIATE_JOINTS(double)
#if SOADYN_FLOAT
SOADYN_INSTANTIATE_JOINTS(float)
#endif

}  // namespace soadyn
