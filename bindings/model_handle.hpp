// The Python-side Model: a soadyn::Model with the Data its calls reuse.
//
// Threading contract (docs/guides/python-api.md, "Threads"): a model may be used from any number
// of Python threads. Dynamics calls on one model are serialised by `mutex`
// (they share `data`); the GIL is released while large models compute.
// Every change of the model (structure, flags, gravity) holds both the GIL
// and `mutex`, so code holding either sees a model that does not change
// under it. A call whose arguments were checked against a model that another
// thread changed before the computation started raises RuntimeError instead
// of computing with arguments of the wrong size.
#pragma once
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>
#include "soadyn/model/data.hpp"

namespace soadyn {
class BatchDynamics;
}

namespace soadyn_py {

struct ModelHandle {
  soadyn::Model model;
  std::unique_ptr<soadyn::Data> data;
  std::mutex mutex;  // serialises calls that share `data` (the GIL is released)
  // The batched calls' pools and per-thread Data (batch_binding.cpp), one per
  // thread count used, the most recently used first, for the model's
  // structure at `batch_version`; guarded by `mutex`.
  std::vector<std::shared_ptr<soadyn::BatchDynamics>> batches;
  std::uint64_t batch_version = 0;
  long batch_pid = 0;  // the process that built `batches` (a forked child rebuilds them)

  ModelHandle() = default;
  ModelHandle(const ModelHandle& other) : model(other.model) {}

  // Call with `mutex` held. Rebuilt only after a structural change.
  soadyn::Data& scratch() {
    if (!data || data->model_version != model.version) data = std::make_unique<soadyn::Data>(model);
    return *data;
  }

  // Replaces the whole model (a copy, a scene); call with lock_for_change()
  // held. Its version moves past the old one, so calls checked against the
  // old model and the Data built for it are never taken for current.
  void replace_model(soadyn::Model&& other) {
    const std::uint64_t old_version = model.version;
    model = std::move(other);
    model.version = std::max(old_version, model.version) + 1;
    data.reset();
  }

  // `mutex` for a computation; call with the GIL held, which stays held. A
  // computation in progress is waited for with the GIL released.
  std::unique_lock<std::mutex> lock_for_computation() {
    std::unique_lock<std::mutex> lock(mutex, std::try_to_lock);
    if (!lock.owns_lock()) {
      pybind11::gil_scoped_release release;
      lock.lock();
    }
    return lock;
  }

  // `mutex` for a change of the model; call with the GIL held, which stays
  // held. While a computation holds the mutex, the GIL is released to wait
  // for it, and the mutex is taken only once the GIL is back, so the change
  // holds both. (Every wait for `mutex` releases the GIL: a thread holding
  // the GIL never blocks on `mutex`, so no two threads wait on each other.)
  std::unique_lock<std::mutex> lock_for_change() {
    std::unique_lock<std::mutex> lock(mutex, std::try_to_lock);
    while (!lock.owns_lock()) {
      {
        pybind11::gil_scoped_release release;
        std::lock_guard<std::mutex> wait_for_computation(mutex);
      }
      lock.try_lock();
    }
    return lock;
  }
};

// Models up to this many DOFs compute in less time than releasing and
// re-taking the GIL costs; larger ones release it so other threads run.
constexpr int kReleaseGilAboveDofs = 24;

// Raised (as RuntimeError) when another thread changed the model's structure
// between the checks of a call's arguments and its computation.
inline void refuse_changed_model(const ModelHandle& h, std::uint64_t checked_version) {
  if (h.model.version != checked_version)
    throw std::runtime_error(
        "the model was changed structurally by another thread (a body added, or the model replaced) while "
        "this call waited for it; its arguments were checked against the model before the change: call again");
}

// Runs `fn(model, data)` with the model's Data locked, and the GIL released
// for models large enough to make it worthwhile. Call with the GIL held;
// `checked_version` is the model's version when the call's arguments were
// checked (a call on a changed model raises RuntimeError).
template <class Fn>
void run_locked(ModelHandle& h, std::uint64_t checked_version, Fn&& fn) {
  if (h.model.nv <= kReleaseGilAboveDofs) {
    const auto lock = h.lock_for_computation();
    refuse_changed_model(h, checked_version);
    fn(h.model, h.scratch());
    return;
  }
  pybind11::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(h.mutex);
  refuse_changed_model(h, checked_version);
  fn(h.model, h.scratch());
}

}  // namespace soadyn_py
