// Ctrl-C for the long computations called from Python (soadyn/core/interrupt.hpp).
//
// The poll looks at Python's pending signals at most every 20 ms of wall
// time, taking the GIL for it when the computation released it. An exception
// that a signal handler raises (KeyboardInterrupt) is kept and raised by
// raise_if_interrupted() once the computation has returned.
#pragma once
#include <pybind11/pybind11.h>

#include <chrono>

#include "soadyn/core/interrupt.hpp"

namespace soadyn_py {

class PythonInterrupt {
 public:
  PythonInterrupt();
  ~PythonInterrupt();
  PythonInterrupt(const PythonInterrupt&) = delete;
  PythonInterrupt& operator=(const PythonInterrupt&) = delete;

  const soadyn::Interrupt* get() const { return &interrupt_; }
  bool interrupted() const { return pending_type_ != nullptr; }
  // With the GIL held: raises the kept exception, if any.
  void raise_if_interrupted();

 private:
  static bool poll(void* self);
  soadyn::Interrupt interrupt_;
  std::chrono::steady_clock::time_point next_check_;
  PyObject *pending_type_ = nullptr, *pending_value_ = nullptr, *pending_traceback_ = nullptr;
};

}  // namespace soadyn_py
