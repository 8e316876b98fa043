// The Python-side Model: a soadyn::Model with the Data its calls reuse.
#pragma once
#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>
#include "soadyn/data.hpp"

namespace soadyn_py {

struct ModelHandle {
  soadyn::Model model;
  std::unique_ptr<soadyn::Data> data;
  std::mutex mutex;  // serialises calls that share `data` (the GIL is released)

  ModelHandle() = default;
  ModelHandle(const ModelHandle& other) : model(other.model) {}

  // Call with `mutex` held. Rebuilt only after a structural change.
  soadyn::Data& scratch() {
    if (!data || data->model_version != model.version) data = std::make_unique<soadyn::Data>(model);
    return *data;
  }
};

// Models up to this many DOFs compute in less time than releasing and
// re-taking the GIL costs; larger ones release it so other threads run.
constexpr int kReleaseGilAboveDofs = 24;

// Runs `fn(model, data)` with the model's Data locked, and the GIL released
// for models large enough to make it worthwhile. Call with the GIL held.
template <class Fn>
void run_locked(ModelHandle& h, Fn&& fn) {
  if (h.model.nv <= kReleaseGilAboveDofs) {
    std::lock_guard<std::mutex> lock(h.mutex);
    fn(h.model, h.scratch());
    return;
  }
  pybind11::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(h.mutex);
  fn(h.model, h.scratch());
}

}  // namespace soadyn_py
