// Failure counting for the C++ tests that check many items: each failed
// check prints what failed, and main's exit code comes from the count.
#pragma once
#include <cstdio>
#include <string>

namespace soadyn_test {

inline int failures = 0;

inline void check(bool ok, const std::string& what) {
  if (!ok) {
    ++failures;
    std::printf("FAIL: %s\n", what.c_str());
  }
}

}  // namespace soadyn_test
