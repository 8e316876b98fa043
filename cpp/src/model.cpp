#include "soadyn/model.hxx"

namespace soadyn {
template class ModelTpl<double>;
template class ModelTpl<float>;
}  // namespace soadyn
