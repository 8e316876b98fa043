// Real-time scheduling of the thread that runs a HIL loop (Linux).
//
// A fixed-rate loop on a shared machine is late when the kernel runs
// something else on its core or when it touches a page that is not resident.
// The usual remedies, each optional and each undone when the loop ends:
//   - SCHED_FIFO at a priority (1-99): no ordinary (SCHED_OTHER) thread
//     preempts the loop; the kernel's real-time throttling
//     (/proc/sys/kernel/sched_rt_runtime_us) still reserves a share for them;
//   - pinning to one CPU: no migration between cores (cold caches);
//   - mlockall(MCL_CURRENT | MCL_FUTURE): no page of the process is paged out
//     or faulted in lazily during the loop.
// Each needs a privilege (CAP_SYS_NICE / an RLIMIT_RTPRIO for SCHED_FIFO,
// CAP_IPC_LOCK / RLIMIT_MEMLOCK for mlockall). A request the kernel refuses
// is not an error: the loop runs anyway and the errno of the refusal is kept,
// so the report says what the run did and did not get.
//
// Apply() and the destructor make system calls: they belong before and
// after the loop, never in it.
#pragma once

namespace soadyn {

struct RealtimeRequest {
  int fifo_priority = 0;     // SCHED_FIFO priority 1..99; 0: keep the thread's policy
  int cpu = -1;              // pin the thread to this CPU; -1: keep its affinity
  bool lock_memory = false;  // mlockall for the loop's duration
  // Throws std::invalid_argument naming the field at fault (priority outside
  // 0..99, CPU below -1 or not online).
  void validate() const;
};

// What the kernel granted: a field is 0 when granted or not asked for, else
// the errno of the refusal.
struct RealtimeOutcome {
  int fifo_errno = 0;
  int cpu_errno = 0;
  int lock_errno = 0;
  bool fifo_granted = false, cpu_granted = false, memory_locked = false;
};

// Applies a request to the calling thread on construction and restores the
// thread's previous policy, priority and affinity on destruction. Memory it
// locked is unlocked with munlockall, which also unlocks pages the process
// had locked itself before: a caller that locks its own memory should do so
// for the whole process and not ask the loop to. Never throws.
class RealtimeScope {
 public:
  explicit RealtimeScope(const RealtimeRequest& request);
  ~RealtimeScope();
  RealtimeScope(const RealtimeScope&) = delete;
  RealtimeScope& operator=(const RealtimeScope&) = delete;
  const RealtimeOutcome& outcome() const { return outcome_; }

 private:
  RealtimeOutcome outcome_;
  int previous_policy_ = 0, previous_priority_ = 0;
  // The thread's cpu_set_t (1024 CPUs; an array of unsigned long), kept
  // opaque so this header includes no system header.
  alignas(unsigned long) unsigned char previous_affinity_[128] = {};
};

}  // namespace soadyn
