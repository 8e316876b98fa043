// A request from outside to stop a long computation early: assembly, statics,
// a simulation run, a batch or a rollout ask `requested()` between their
// iterations (never inside a real-time step). The Python bindings make it
// answer Ctrl-C; C++ callers pass nothing (nullptr) or their own poll.
//
// `poll(context)` must be cheap, must not throw, and may be called from the
// thread that started the computation only.
#pragma once

namespace soadyn {

struct Interrupt {
  bool (*poll)(void* context) = nullptr;
  void* context = nullptr;
  bool requested() const { return poll != nullptr && poll(context); }
};

// Whether `interrupt` (may be null) asks to stop.
inline bool interrupt_requested(const Interrupt* interrupt) { return interrupt != nullptr && interrupt->requested(); }

}  // namespace soadyn
