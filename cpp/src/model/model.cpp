#include "soadyn/model/model.hxx"

namespace soadyn {
template class ModelTpl<double>;
#if SOADYN_FLOAT
template class ModelTpl<float>;
#endif
}  // namespace soadyn
