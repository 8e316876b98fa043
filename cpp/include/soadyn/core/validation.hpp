// Helpers shared by the construction-time checks (model, flexible bodies).
#pragma once
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace soadyn::detail {

// Relative tolerance of the symmetry, orthonormality and definiteness tests.
template <class S>
S validation_tolerance() {
  using std::sqrt;
  return sqrt(std::numeric_limits<S>::epsilon());
}

// A number as text for error messages.
template <class S>
std::string to_text(const S& x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

}  // namespace soadyn::detail
