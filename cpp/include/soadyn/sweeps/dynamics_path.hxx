// The one place that chooses which sweeps forward dynamics, hybrid dynamics
// and its impulse form run: the model's DynamicsPath (model.hpp), fixed when
// its structure changes, and per call the tree-frame reach
// (tree_frame_reach.hxx). docs/design/layout.md tabulates it.
#pragma once
#include "soadyn/sweeps/body_frame_sweeps.hxx"
#include "soadyn/sweeps/tree_frame_sweeps.hxx"

namespace soadyn {
namespace detail {

// The tree-frame sweeps under `Modes`; under the model's flags, a model
// whose every body has an articulated inertia (a regular hinge at each root)
// runs the variant without the Newton-Euler branches.
template <ModePolicy Modes, bool Flex, class S>
TreeFrameStatus tree_frame_sweeps_for(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u,
                                      const S* f_ext, const Vec6<S>& world_acc, bool want_force) {
  if constexpr (Modes == ModePolicy::model_flags) {
    if (!m.has_newton_euler_region)
      return tree_frame_sweeps<ModePolicy::model_flags_articulated, Flex>(m, d, q, v, u, f_ext, world_acc,
                                                                          want_force);
  }
  return tree_frame_sweeps<Modes, Flex>(m, d, q, v, u, f_ext, world_acc, want_force);
}

// Runs the hybrid algorithm's sweeps on the model's path: `Modes` is
// model_flags (hybrid dynamics, impulse form) or all_regular (forward
// dynamics); arguments as body_frame_sweeps. A tree-frame path that meets a
// body beyond its reach has changed no output and hands over to body frames.
// Scalars other than double and float take body frames (has_speed_paths).
template <ModePolicy Modes, class S>
Status dynamics_sweeps(const ModelTpl<S>& m, DataTpl<S>& d, const S* q, const S* v, const S* u, const S* f_ext,
                       const Vec6<S>& world_acc, bool want_force) {
  if constexpr (has_speed_paths<S>) {
    switch (m.dynamics_path) {
      case DynamicsPath::rigid_tree_frames: {
        const S* v_unless_at_rest = detail::velocities_unless_at_rest(m, v);
        const TreeFrameStatus s =
            tree_frame_sweeps_for<Modes, false>(m, d, q, v_unless_at_rest, u, f_ext, world_acc, want_force);
        if (!s.beyond_reach) return s.status;
        break;
      }
      case DynamicsPath::appendage_tree_frames: {
        const TreeFrameStatus s = tree_frame_sweeps_for<Modes, true>(m, d, q, v, u, f_ext, world_acc, want_force);
        if (!s.beyond_reach) return s.status;
        break;
      }
      case DynamicsPath::body_frames: break;
    }
  }
  return body_frame_sweeps<Modes>(m, d, q, v, u, f_ext, world_acc, want_force);
}

// Compiled once, in sweeps/dynamics_sweeps.cpp, for double (and float):
// forward dynamics, hybrid dynamics, its impulse form and the loop solves
// of models without loops call that code.
#define SOADYN_DYNAMICS_SWEEPS(MODES, S)                                                                      \
  template Status dynamics_sweeps<MODES, S>(const ModelTpl<S>&, DataTpl<S>&, const S*, const S*, const S*, \
                                            const S*, const Vec6<S>&, bool);
extern SOADYN_DYNAMICS_SWEEPS(ModePolicy::all_regular, double)
extern SOADYN_DYNAMICS_SWEEPS(ModePolicy::model_flags, double)
#if SOADYN_FLOAT
extern SOADYN_DYNAMICS_SWEEPS(ModePolicy::all_regular, float)
extern SOADYN_DYNAMICS_SWEEPS(ModePolicy::model_flags, float)
#endif

}  // namespace detail
}  // namespace soadyn
