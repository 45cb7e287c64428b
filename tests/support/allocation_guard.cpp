#include "support/allocation_guard.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<std::size_t> g_allocations{0};
std::atomic<std::size_t> g_bytes{0};

void count(std::size_t bytes) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  g_bytes.fetch_add(bytes, std::memory_order_relaxed);
}

}  // namespace

#if defined(NAV_ALLOCATION_GUARD_MALLOC_HOOKS)
// glibc's own entry points, so the hooks can count and forward.
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t size) {
  count(size);
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  count(n * size);
  return __libc_calloc(n, size);
}
void* realloc(void* pointer, std::size_t size) {
  count(size);
  return __libc_realloc(pointer, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  count(size);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  count(size);
  *out = __libc_memalign(alignment, size);
  return *out ? 0 : 12;  // ENOMEM
}
void free(void* pointer) { __libc_free(pointer); }
}
#define NAV_RAW_ALLOCATE(size) __libc_malloc(size)
#define NAV_RAW_ALIGNED_ALLOCATE(alignment, size) __libc_memalign(alignment, size)
#define NAV_RAW_FREE(pointer) __libc_free(pointer)
#else
#define NAV_RAW_ALLOCATE(size) std::malloc(size)
#define NAV_RAW_ALIGNED_ALLOCATE(alignment, size) \
  std::aligned_alloc(alignment, ((size) + (alignment)-1) / (alignment) * (alignment))
#define NAV_RAW_FREE(pointer) std::free(pointer)
#endif

namespace {

void* counted_new(std::size_t size) {
  count(size);
  void* pointer = NAV_RAW_ALLOCATE(size == 0 ? 1 : size);
  if (pointer == nullptr) throw std::bad_alloc();
  return pointer;
}

void* counted_aligned_new(std::size_t size, std::align_val_t alignment) {
  count(size);
  void* pointer = NAV_RAW_ALIGNED_ALLOCATE(static_cast<std::size_t>(alignment), size == 0 ? 1 : size);
  if (pointer == nullptr) throw std::bad_alloc();
  return pointer;
}

/// What `allocate` returns, or null where it throws (the nothrow forms).
template <typename Allocate>
void* or_null(Allocate allocate) noexcept {
  try {
    return allocate();
  } catch (...) {
    return nullptr;
  }
}

}  // namespace

// Every replaceable form, so that no sanitizer runtime's own definitions are linked beside these.
void* operator new(std::size_t size) { return counted_new(size); }
void* operator new[](std::size_t size) { return counted_new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return or_null([&] { return counted_new(size); });
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return or_null([&] { return counted_new(size); });
}
void* operator new(std::size_t size, std::align_val_t alignment) { return counted_aligned_new(size, alignment); }
void* operator new[](std::size_t size, std::align_val_t alignment) { return counted_aligned_new(size, alignment); }
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return or_null([&] { return counted_aligned_new(size, alignment); });
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return or_null([&] { return counted_aligned_new(size, alignment); });
}
void operator delete(void* pointer) noexcept { NAV_RAW_FREE(pointer); }
void operator delete[](void* pointer) noexcept { NAV_RAW_FREE(pointer); }
void operator delete(void* pointer, const std::nothrow_t&) noexcept { NAV_RAW_FREE(pointer); }
void operator delete[](void* pointer, const std::nothrow_t&) noexcept { NAV_RAW_FREE(pointer); }
void operator delete(void* pointer, std::size_t) noexcept { NAV_RAW_FREE(pointer); }
void operator delete[](void* pointer, std::size_t) noexcept { NAV_RAW_FREE(pointer); }
void operator delete(void* pointer, std::align_val_t) noexcept { NAV_RAW_FREE(pointer); }
void operator delete[](void* pointer, std::align_val_t) noexcept { NAV_RAW_FREE(pointer); }
void operator delete(void* pointer, std::align_val_t, const std::nothrow_t&) noexcept { NAV_RAW_FREE(pointer); }
void operator delete[](void* pointer, std::align_val_t, const std::nothrow_t&) noexcept { NAV_RAW_FREE(pointer); }
void operator delete(void* pointer, std::size_t, std::align_val_t) noexcept { NAV_RAW_FREE(pointer); }
void operator delete[](void* pointer, std::size_t, std::align_val_t) noexcept { NAV_RAW_FREE(pointer); }

namespace nav::testing {

AllocationGuard::AllocationGuard()
    : start_allocations_(g_allocations.load(std::memory_order_seq_cst)),
      start_bytes_(g_bytes.load(std::memory_order_seq_cst)) {}

AllocationGuard::~AllocationGuard() = default;

std::size_t AllocationGuard::allocations() const {
  return g_allocations.load(std::memory_order_seq_cst) - start_allocations_;
}

std::size_t AllocationGuard::bytes() const { return g_bytes.load(std::memory_order_seq_cst) - start_bytes_; }

bool allocation_guard_hooks_malloc() {
#if defined(NAV_ALLOCATION_GUARD_MALLOC_HOOKS)
  return true;
#else
  return false;
#endif
}

}  // namespace nav::testing
