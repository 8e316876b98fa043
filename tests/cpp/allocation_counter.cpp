// Replaces every allocation function of the process: all operator new/delete
// variants (plain, array, sized, aligned, nothrow) and the C family (malloc,
// calloc, realloc, aligned_alloc, posix_memalign, memalign, free), which
// forward to glibc's own allocator (__libc_*). While the counter is armed
// every call is counted, whoever makes it: the library, Eigen, libstdc++ or
// libc. Link this file into a test executable to count its allocations.
#include "allocation_counter.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

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

}  // namespace

namespace soadyn_test {

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

}  // namespace soadyn_test

namespace {

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

}  // namespace

namespace soadyn_test {

bool allocation_counter_works(std::size_t probe_size) {
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

}  // namespace soadyn_test
