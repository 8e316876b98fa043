// The run-time algorithms never touch the heap.
//
// Every allocation function of the process is replaced here: all operator
// new/delete variants (plain, array, sized, aligned, nothrow) and the C
// family (malloc, calloc, realloc, aligned_alloc, posix_memalign, memalign,
// free), which forward to glibc's own allocator (__libc_*). While the counter
// is armed every call is counted, whoever makes it: the library, Eigen,
// libstdc++ or libc. A self-check first proves that the counter sees each
// family, so the test cannot pass vacuously.
//
// The workload: a random 20-body tree with every joint type, 10^5
// hybrid_dynamics calls each preceded by a random flag change of a few DOFs,
// with and without external wrenches and hinge-force outputs, interleaved
// with the other run-time algorithms. Zero allocations, zero frees and every
// Status ok are required.
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <set>
#include <vector>
#include "random_tree.hpp"

// ---------------------------------------------------------------------------
// Allocation counter
// ---------------------------------------------------------------------------

namespace {

// Plain atomics: constant-initialised, so usable by allocations made before
// main() and by static constructors.
std::atomic<bool> g_armed{false};
std::atomic<long> g_operator_new{0};  // operator new / new[], every variant
std::atomic<long> g_c_alloc{0};       // malloc, calloc, realloc, aligned_alloc, posix_memalign, memalign
std::atomic<long> g_frees{0};         // operator delete / delete[] and free of a non-null pointer

void count(std::atomic<long>& counter) {
  if (g_armed.load(std::memory_order_relaxed)) counter.fetch_add(1, std::memory_order_relaxed);
}
void count_free(void* p) {
  if (p) count(g_frees);
}

struct AllocationCounts {
  long operator_new, c_alloc, frees;
  long allocations() const { return operator_new + c_alloc; }
};

void arm_counter() {
  g_operator_new = 0;
  g_c_alloc = 0;
  g_frees = 0;
  g_armed = true;
}

AllocationCounts disarm_counter() {
  g_armed = false;
  return AllocationCounts{g_operator_new.load(), g_c_alloc.load(), g_frees.load()};
}

bool valid_alignment(std::size_t alignment) {
  return alignment >= sizeof(void*) && (alignment & (alignment - 1)) == 0;
}

}  // namespace

// glibc's allocator under its internal names: what the replacements forward to.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* p);
}

// The C family. glibc declares these noexcept in C++, so the definitions are too.
extern "C" {
void* malloc(std::size_t size) noexcept {
  count(g_c_alloc);
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) noexcept {
  count(g_c_alloc);
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  count(g_c_alloc);
  return __libc_realloc(p, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  count(g_c_alloc);
  return __libc_memalign(alignment, size);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  count(g_c_alloc);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  count(g_c_alloc);
  if (!valid_alignment(alignment)) return EINVAL;
  void* p = __libc_memalign(alignment, size);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
void free(void* p) noexcept {
  count_free(p);
  __libc_free(p);
}
}  // extern "C"

// The C++ family: every replaceable global operator new and delete.
namespace {
void* counted_new(std::size_t size) noexcept {
  count(g_operator_new);
  return __libc_malloc(size ? size : 1);
}
void* counted_aligned_new(std::size_t size, std::align_val_t alignment) noexcept {
  count(g_operator_new);
  return __libc_memalign(static_cast<std::size_t>(alignment), size ? size : 1);
}
void* or_throw(void* p) {
  if (!p) throw std::bad_alloc();
  return p;
}
void counted_delete(void* p) noexcept {
  count_free(p);
  __libc_free(p);
}
}  // namespace

void* operator new(std::size_t n) { return or_throw(counted_new(n)); }
void* operator new[](std::size_t n) { return or_throw(counted_new(n)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_new(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_new(n); }
void* operator new(std::size_t n, std::align_val_t a) { return or_throw(counted_aligned_new(n, a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return or_throw(counted_aligned_new(n, a)); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_aligned_new(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_aligned_new(n, a);
}
void operator delete(void* p) noexcept { counted_delete(p); }
void operator delete[](void* p) noexcept { counted_delete(p); }
void operator delete(void* p, std::size_t) noexcept { counted_delete(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_delete(p); }
void operator delete(void* p, std::align_val_t) noexcept { counted_delete(p); }
void operator delete[](void* p, std::align_val_t) noexcept { counted_delete(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { counted_delete(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { counted_delete(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_delete(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_delete(p); }

// ---------------------------------------------------------------------------
// Self-check: the counter sees std::vector (operator new), aligned operator
// new, and malloc called from inside libc (strdup).
// ---------------------------------------------------------------------------

namespace {

// Pointers stored here escape, so the compiler cannot elide the allocations.
void* volatile g_escape = nullptr;

struct alignas(64) OverAligned {
  double x[8];
};

bool counter_works(std::size_t probe_size) {
  arm_counter();
  {
    std::vector<double> probe(probe_size);
    g_escape = probe.data();
  }
  const AllocationCounts after_vector = disarm_counter();

  arm_counter();
  OverAligned* block = new OverAligned();
  g_escape = block;
  delete block;
  const AllocationCounts after_aligned = disarm_counter();

  arm_counter();
  char* copy = strdup("soadyn");
  g_escape = copy;
  free(copy);
  const AllocationCounts after_strdup = disarm_counter();

  std::printf("self-check: std::vector -> %ld new / %ld free, aligned new -> %ld new / %ld free, "
              "strdup -> %ld malloc / %ld free\n",
              after_vector.operator_new, after_vector.frees, after_aligned.operator_new, after_aligned.frees,
              after_strdup.c_alloc, after_strdup.frees);
  return after_vector.operator_new >= 1 && after_vector.frees >= 1 && after_aligned.operator_new >= 1 &&
         after_aligned.frees >= 1 && after_strdup.c_alloc >= 1 && after_strdup.frees >= 1;
}

// ---------------------------------------------------------------------------
// Workload
// ---------------------------------------------------------------------------

constexpr int kHybridCalls = 100000;
constexpr int kOtherAlgorithmsEvery = 10;   // forward/inverse dynamics, M, h, integrate
constexpr int kSetAllFlagsEvery = 997;      // also exercise set_all_prescribed
constexpr int kStates = 16;

struct Tally {
  long hybrid_calls = 0, other_calls = 0, flag_changes = 0, failed_statuses = 0;
  soadyn::Status first_failure;
  int first_failure_call = -1;

  void check(const soadyn::Status& s, int call) {
    if (s.ok()) return;
    if (failed_statuses++ == 0) first_failure = s, first_failure_call = call;
  }
};

// Flips a few DOFs to a random mode (the model is shared by every state).
void change_random_flags(soadyn::Model& model, std::mt19937_64& rng, Tally& tally) {
  std::uniform_int_distribution<int> how_many(1, 3), dof(0, model.nv - 1), flag(0, 1);
  for (int k = how_many(rng); k > 0; --k, ++tally.flag_changes) model.set_prescribed(dof(rng), flag(rng) != 0);
}

void run_other_algorithms(const soadyn::Model& model, soadyn::Data& data, const soadyn_test::State& s,
                          Eigen::VectorXd& q_next, int call, Tally& tally) {
  tally.check(soadyn::forward_dynamics(model, data, s.q, s.v, s.u, s.f_ext.data()), call);
  soadyn::inverse_dynamics(model, data, s.q, s.v, s.u, s.f_ext.data());
  soadyn::mass_matrix(model, data, s.q);
  soadyn::bias_forces(model, data, s.q, s.v);
  soadyn::integrate(model, s.q, s.v, 1e-3, q_next);
  tally.check(soadyn::hybrid_impulse(model, data, s.q, s.u), call);  // lock impacts use it
  tally.other_calls += 6;
}

// The armed section: nothing here may allocate, print or throw.
Tally run_workload(soadyn::Model& model, soadyn::Data& data, const std::vector<soadyn_test::State>& states,
                   Eigen::VectorXd& q_next) {
  Tally tally;
  std::mt19937_64 rng(7);
  for (int call = 0; call < kHybridCalls; ++call) {
    if (call % kSetAllFlagsEvery == 0) model.set_all_prescribed((call / kSetAllFlagsEvery) % 2 == 0);
    change_random_flags(model, rng, tally);
    const soadyn_test::State& s = states[static_cast<std::size_t>(call % kStates)];
    const double* f_ext = call % 2 ? s.f_ext.data() : nullptr;
    const soadyn::HybridOutputs outputs{call % 3 == 0};
    tally.check(soadyn::hybrid_dynamics(model, data, s.q, s.v, s.u, f_ext, outputs), call);
    ++tally.hybrid_calls;
    if (call % kOtherAlgorithmsEvery == 0) run_other_algorithms(model, data, s, q_next, call, tally);
  }
  return tally;
}

// The workload must reach every joint type's code: the tree holds every
// movable joint type (fixed joints are merged away and never reach the model).
bool has_every_joint_type(const soadyn::Model& model) {
  std::set<std::size_t> types;
  for (const soadyn::JointModel<double>& joint : model.joints) types.insert(joint.index());
  return types.size() == soadyn_test::all_joint_kinds().size();
}

}  // namespace

int main(int argc, char**) {
  // The probe size depends on run-time input so it cannot be folded away.
  if (!counter_works(static_cast<std::size_t>(16 + argc))) {
    std::printf("test_no_allocation: FAIL: the allocation counter does not see allocations\n");
    return 1;
  }

  soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(2024, 20));
  soadyn::Data data(model);
  std::vector<soadyn_test::State> states;
  for (int k = 0; k < kStates; ++k) states.push_back(soadyn_test::random_state(model, 100 + k));
  Eigen::VectorXd q_next(model.nq);
  std::printf("model: %d bodies, nq = %d, nv = %d\n", model.nbodies(), model.nq, model.nv);
  if (!has_every_joint_type(model)) {
    std::printf("test_no_allocation: FAIL: the random tree lacks a joint type\n");
    return 1;
  }

  arm_counter();
  const Tally tally = run_workload(model, data, states, q_next);
  const AllocationCounts counts = disarm_counter();

  std::printf("calls: %ld hybrid_dynamics, %ld other, %ld flag changes; failed statuses: %ld\n", tally.hybrid_calls,
              tally.other_calls, tally.flag_changes, tally.failed_statuses);
  std::printf("allocations: %ld operator new, %ld malloc family; frees: %ld\n", counts.operator_new, counts.c_alloc,
              counts.frees);
  if (tally.failed_statuses > 0)
    std::printf("first failure: call %d, status code %d, dof %d\n", tally.first_failure_call,
                static_cast<int>(tally.first_failure.code), tally.first_failure.index);
  const bool pass = counts.allocations() == 0 && counts.frees == 0 && tally.failed_statuses == 0;
  std::printf("test_no_allocation: %s: %ld hybrid_dynamics calls, %ld allocations, %ld frees, %ld failed statuses\n",
              pass ? "PASS" : "FAIL", tally.hybrid_calls, counts.allocations(), counts.frees, tally.failed_statuses);
  return pass ? 0 : 1;
}
