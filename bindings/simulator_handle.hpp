// The Python-side Simulator: a soadyn::Simulator with the lock that
// serialises the calls Python makes on it from any number of threads.
//
// Lock order: the simulator's lock before the GIL. A thread that must wait
// for the lock waits with the GIL released, so the thread holding the lock can
// always take the GIL (a Python motion source does, inside a step). A thread
// that already holds the lock (a motion source calling its own simulator) is
// refused with RuntimeError instead of deadlocking. Taking the lock allocates
// nothing; the C++ step itself takes no lock.
#pragma once
#include <pybind11/pybind11.h>

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include "soadyn/sim/simulator.hpp"

namespace soadyn_py {

// A motion source as a Python object (a struct, so pybind11 does not turn the
// variant into its alternatives).
struct Source {
  soadyn::MotionSource<double> source;
};

struct SimulatorHandle : soadyn::Simulator {
  using soadyn::Simulator::Simulator;
  std::mutex mutex;
  std::atomic<std::thread::id> holder{};  // the thread holding `mutex`, if any
};

// Holds a SimulatorHandle's lock for a scope. Construct with the GIL held.
class SimulatorLock {
 public:
  explicit SimulatorLock(SimulatorHandle& sim) : sim_(sim) {
    if (sim_.holder.load() == std::this_thread::get_id())
      throw std::runtime_error("the simulator is in use by this thread (a motion source cannot call its own simulator)");
    if (!sim_.mutex.try_lock()) {
      pybind11::gil_scoped_release release;  // wait without the GIL
      sim_.mutex.lock();
    }
    sim_.holder.store(std::this_thread::get_id());
  }
  ~SimulatorLock() {
    sim_.holder.store(std::thread::id());
    sim_.mutex.unlock();
  }
  SimulatorLock(const SimulatorLock&) = delete;
  SimulatorLock& operator=(const SimulatorLock&) = delete;

 private:
  SimulatorHandle& sim_;
};

// Call with the GIL held, after a step or a loop of steps ran on this
// thread and returned `s`: when a Python motion source raised during it,
// raises the DynamicsError naming the DOF with that exception as its cause
// (the error Simulator.step raises); otherwise returns. Defined in
// simulator_binding.cpp.
void raise_if_source_raised(const SimulatorHandle& sim, const soadyn::Status& s);

// Forgets an exception a Python source raised earlier on this thread and
// that was never reported; call with the GIL held before a step or loop.
void forget_pending_source_error();

// The integrator named "euler" (or "semi-implicit-euler"), "rk4" or "dopri5";
// ValueError otherwise.
soadyn::Integrator integrator_from(const std::string& name);

}  // namespace soadyn_py
