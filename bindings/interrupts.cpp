#include "interrupts.hpp"

namespace soadyn_py {

namespace {
constexpr std::chrono::milliseconds signal_check_period{20};
}

PythonInterrupt::PythonInterrupt() : next_check_(std::chrono::steady_clock::now() + signal_check_period) {
  interrupt_.poll = &PythonInterrupt::poll;
  interrupt_.context = this;
}

PythonInterrupt::~PythonInterrupt() {
  if (!interrupted()) return;
  pybind11::gil_scoped_acquire gil;
  Py_XDECREF(pending_type_);
  Py_XDECREF(pending_value_);
  Py_XDECREF(pending_traceback_);
}

bool PythonInterrupt::poll(void* context) {
  auto& self = *static_cast<PythonInterrupt*>(context);
  if (self.interrupted()) return true;
  const auto now = std::chrono::steady_clock::now();
  if (now < self.next_check_) return false;
  self.next_check_ = now + signal_check_period;
  const auto check = [&] {
    if (PyErr_CheckSignals() == 0) return;
    PyErr_Fetch(&self.pending_type_, &self.pending_value_, &self.pending_traceback_);
  };
  if (PyGILState_Check()) {
    check();
  } else {
    pybind11::gil_scoped_acquire gil;
    check();
  }
  return self.interrupted();
}

void PythonInterrupt::raise_if_interrupted() {
  if (!interrupted()) return;
  PyErr_Restore(pending_type_, pending_value_, pending_traceback_);
  pending_type_ = pending_value_ = pending_traceback_ = nullptr;
  throw pybind11::error_already_set();
}

}  // namespace soadyn_py
