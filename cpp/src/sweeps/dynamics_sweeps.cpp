// The hybrid algorithm's sweeps on each dynamics path (dynamics_path.hxx),
// for all-regular models (forward dynamics) and under the model's flags
// (hybrid dynamics), compiled once for every caller.
#include "soadyn/sweeps/dynamics_path.hxx"

namespace soadyn {
namespace detail {
SOADYN_DYNAMICS_SWEEPS(ModePolicy::all_regular, double)
SOADYN_DYNAMICS_SWEEPS(ModePolicy::model_flags, double)
#if SOADYN_FLOAT
SOADYN_DYNAMICS_SWEEPS(ModePolicy::all_regular, float)
SOADYN_DYNAMICS_SWEEPS(ModePolicy::model_flags, float)
#endif
}  // namespace detail
}  // namespace soadyn
