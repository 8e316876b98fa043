// Model files: a documented, versioned JSON text that holds everything a
// Model holds, so that a model built anywhere (Python, a URDF or MJCF
// loader, C++) can be shipped to a C++ simulator or a campaign worker and
// rebuilt exactly (every double written with the 17 significant digits that
// round-trip). The format ("format": "soadyn-model", "version": 1) is
// described key by key in docs/guides/model-files.md; a reader refuses a
// newer version, an unknown joint type or loop kind, a missing or mistyped
// key and a non-finite number with a ModelFileError naming the file and the
// JSON path of the item (e.g. "/bodies/3/mass"). Unknown keys are refused
// too (a misspelt key must not be silently ignored), except inside
// "description", which is kept as it is: the description's visuals and
// metadata are not dynamics, and a C++ load/save round trip preserves them.
//
// Only this header's functions touch the JSON library (one translation
// unit: src/model_file.cpp). Models in double precision.
#pragma once
#include <stdexcept>
#include <string>

#include "soadyn/model/model.hpp"

namespace soadyn {

struct ModelFileError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

inline constexpr int model_file_version = 1;

// Limits of what a model file may hold, checked before anything else is
// read, so that an untrusted file cannot exhaust the stack or the memory:
// arrays and objects nested at most model_file_max_depth levels (the deepest
// a model writes is under 10; the caller's metadata has the rest), and at
// most model_file_max_bytes bytes. The Python readers use the same numbers.
inline constexpr int model_file_max_depth = 256;
inline constexpr std::size_t model_file_max_bytes = std::size_t(1) << 29;  // 512 MiB

// The model as JSON text (indented, numbers exact).
std::string model_to_json(const Model& model);
// The model written in `text`; `source` names it in errors (a file name).
Model model_from_json(const std::string& text, const std::string& source = "model JSON");

// The same through a file; ModelFileError names the path when it cannot be
// read or written.
void save_model(const Model& model, const std::string& path);
Model load_model(const std::string& path);

}  // namespace soadyn
