// The impulse form of constrained_dynamics (constrained_dynamics.hpp): the
// velocity jumps dv when prescribed DOFs jump (a lock, a source taking over)
// in a model with closed loops. Regular DOFs receive no generalized impulse;
// the cut joints receive whatever impulse keeps the loops closed:
//   M dv = iota + C' Lambda,   C (v + dv) = 0,   dv_p = u_p
// (the velocity-level counterpart of "Joint Coordinate Method, Part 1",
// Eq. 1.13). A lock can change the loops' mobility (locking a four-bar's
// rocker locks the crank too): the solve needs no case for it, redundant
// equations taking their minimum-norm impulses. When the prescribed jumps
// contradict the closure, the answer is the least-squares one and C (v + dv)
// is not zero. Without loops this is hybrid_impulse. Allocation free.
#pragma once
#include "soadyn/sweeps/body_updates.hpp"

namespace soadyn {

// data.qdd = dv; data.tau = the generalized impulses (those of prescribed DOFs
// are what the drive applied); data.loops.multipliers = the cut impulses.
template <class S>
Status constrained_impulse(const ModelTpl<S>& model, DataTpl<S>& data, const ConstVecRef<S>& q,
                           const ConstVecRef<S>& v, const ConstVecRef<S>& u);

}  // namespace soadyn
