#include "soadyn/parameters.hxx"

namespace soadyn {
template class ParameterTable<double>;
template class ParameterTable<float>;
}  // namespace soadyn
