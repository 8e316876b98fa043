// Real-time scheduling of the HIL loop's thread; see realtime_scheduling.hpp.
#include "soadyn/realtime/realtime_scheduling.hpp"

#include <cerrno>
#include <stdexcept>
#include <string>

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace soadyn {

void RealtimeRequest::validate() const {
  if (fifo_priority < 0 || fifo_priority > 99)
    throw std::invalid_argument("real-time priority " + std::to_string(fifo_priority) +
                                ": SCHED_FIFO priorities are 1..99 (0 keeps the thread's policy)");
  if (cpu < -1) throw std::invalid_argument("CPU " + std::to_string(cpu) + ": a CPU index is >= 0 (-1: any CPU)");
#ifdef __linux__
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  if (cpu >= 0 && online > 0 && cpu >= online)
    throw std::invalid_argument("CPU " + std::to_string(cpu) + ": this machine has CPUs 0.." +
                                std::to_string(online - 1));
#endif
}

#ifdef __linux__
static_assert(sizeof(cpu_set_t) <= 128 && alignof(cpu_set_t) <= alignof(unsigned long),
              "the saved affinity must hold a cpu_set_t");

RealtimeScope::RealtimeScope(const RealtimeRequest& request) {
  const pthread_t self = pthread_self();
  sched_param param{};
  pthread_getschedparam(self, &previous_policy_, &param);
  previous_priority_ = param.sched_priority;
  cpu_set_t* saved = reinterpret_cast<cpu_set_t*>(previous_affinity_);
  pthread_getaffinity_np(self, sizeof(cpu_set_t), saved);
  if (request.lock_memory) {
    outcome_.lock_errno = mlockall(MCL_CURRENT | MCL_FUTURE) == 0 ? 0 : errno;
    outcome_.memory_locked = outcome_.lock_errno == 0;
  }
  if (request.cpu >= 0) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(request.cpu, &one);
    outcome_.cpu_errno = pthread_setaffinity_np(self, sizeof(one), &one);
    outcome_.cpu_granted = outcome_.cpu_errno == 0;
  }
  if (request.fifo_priority > 0) {
    sched_param fifo{};
    fifo.sched_priority = request.fifo_priority;
    outcome_.fifo_errno = pthread_setschedparam(self, SCHED_FIFO, &fifo);
    outcome_.fifo_granted = outcome_.fifo_errno == 0;
  }
}

RealtimeScope::~RealtimeScope() {
  const pthread_t self = pthread_self();
  if (outcome_.fifo_granted) {
    sched_param param{};
    param.sched_priority = previous_priority_;
    pthread_setschedparam(self, previous_policy_, &param);
  }
  if (outcome_.cpu_granted)
    pthread_setaffinity_np(self, sizeof(cpu_set_t), reinterpret_cast<const cpu_set_t*>(previous_affinity_));
  if (outcome_.memory_locked) munlockall();
}
#else  // no real-time scheduling on this platform: every request is refused with ENOSYS
RealtimeScope::RealtimeScope(const RealtimeRequest& request) {
  if (request.lock_memory) outcome_.lock_errno = ENOSYS;
  if (request.cpu >= 0) outcome_.cpu_errno = ENOSYS;
  if (request.fifo_priority > 0) outcome_.fifo_errno = ENOSYS;
}
RealtimeScope::~RealtimeScope() = default;
#endif

}  // namespace soadyn
