#include "soadyn/model/parameters.hxx"

namespace soadyn {
template class ParameterTable<double>;
#if SOADYN_FLOAT
template class ParameterTable<float>;
#endif
}  // namespace soadyn
