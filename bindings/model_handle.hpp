// The Python-side Model: a soadyn::Model with the Data its calls reuse.
#pragma once
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

}  // namespace soadyn_py
