// FMU states (FMI's GetFMUState ... DeserializeFMUState), shared by the fmi2 and fmi3 entry points: an
// opaque object holding the instance's state bytes (Instance::save_state). Capturing into an existing
// state object reuses it; these are the only FMU calls that allocate (a new state object).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "soadyn/fmu/instance.hpp"

namespace soadyn::fmu {

struct SavedState {
  std::vector<unsigned char> bytes;
};

// The instance's state into `existing` (or a new object when null); returns it.
SavedState* capture_state(Instance& instance, void* existing);
bool restore_state(Instance& instance, const void* state);
void free_state(void* state);
std::size_t serialized_size(const void* state);
bool serialize_state(const void* state, unsigned char* out, std::size_t size);
// A state object from serialized bytes; null (with `why` set) for bytes of the wrong size for this instance.
SavedState* deserialize_state(const Instance& instance, const unsigned char* bytes, std::size_t size, void* existing,
                              std::string& why);

// The local path of an FMI 2 resource location (a file URI: file:///dir, file:/dir, file://localhost/dir,
// percent-encoded); throws std::invalid_argument for another scheme.
std::string path_of_file_uri(const std::string& uri);

}  // namespace soadyn::fmu
