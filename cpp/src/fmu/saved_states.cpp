#include "soadyn/fmu/saved_states.hpp"

#include <cstring>
#include <stdexcept>

namespace soadyn::fmu {

SavedState* capture_state(Instance& instance, void* existing) {
  auto* state = existing ? static_cast<SavedState*>(existing) : new SavedState;
  state->bytes.resize(instance.state_size());
  instance.save_state(state->bytes.data());
  return state;
}

bool restore_state(Instance& instance, const void* state) {
  if (state == nullptr) return false;
  const auto* saved = static_cast<const SavedState*>(state);
  return instance.load_state(saved->bytes.data(), saved->bytes.size());
}

void free_state(void* state) { delete static_cast<SavedState*>(state); }

std::size_t serialized_size(const void* state) { return static_cast<const SavedState*>(state)->bytes.size(); }

bool serialize_state(const void* state, unsigned char* out, std::size_t size) {
  const auto* saved = static_cast<const SavedState*>(state);
  if (out == nullptr || size < saved->bytes.size()) return false;
  std::memcpy(out, saved->bytes.data(), saved->bytes.size());
  return true;
}

SavedState* deserialize_state(const Instance& instance, const unsigned char* bytes, std::size_t size, void* existing,
                              std::string& why) {
  if (bytes == nullptr || size != instance.state_size()) {
    why = "the serialized state has " + std::to_string(size) + " bytes, this FMU's states have " +
          std::to_string(instance.state_size());
    return nullptr;
  }
  auto* state = existing ? static_cast<SavedState*>(existing) : new SavedState;
  state->bytes.assign(bytes, bytes + size);
  return state;
}

std::string path_of_file_uri(const std::string& uri) {
  std::string rest;
  if (uri.rfind("file://localhost/", 0) == 0) rest = uri.substr(16);
  else if (uri.rfind("file:///", 0) == 0) rest = uri.substr(7);
  else if (uri.rfind("file:/", 0) == 0) rest = uri.substr(5);
  else throw std::invalid_argument("the resource location '" + uri + "' is not a file URI");
  std::string path;
  for (std::size_t k = 0; k < rest.size(); ++k) {
    if (rest[k] == '%' && k + 2 < rest.size()) {
      path += static_cast<char>(std::stoi(rest.substr(k + 1, 2), nullptr, 16));
      k += 2;
    } else {
      path += rest[k];
    }
  }
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

}  // namespace soadyn::fmu
