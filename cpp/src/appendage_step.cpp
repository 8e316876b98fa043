// The flexible-appendage step for each mode count up to
// max_fixed_appendage_modes, and for any count (appendage_step.hpp).
#include "soadyn/algorithms/appendage_step.hpp"
#include "soadyn/flex/modal_integrals.hxx"

namespace soadyn {
SOADYN_APPENDAGE_TERMS_ALL(, double)
SOADYN_APPENDAGE_TERMS_ALL(, float)
}  // namespace soadyn
