#include "support/allocation_guard.hpp"

#include <atomic>
#include <cstdio>
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

#if defined(NAV_ALLOCATION_GUARD_SANITIZER_HOOKS)
// A sanitizer owns malloc and operator new (and links its own definitions of every form): it
// reports each allocation of either, on any thread, to the hooks installed here.
#include <sanitizer/allocator_interface.h>

namespace {

void on_allocation(const volatile void*, std::size_t bytes) { count(bytes); }
void on_free(const volatile void*) {}
const int g_sanitizer_hooks = __sanitizer_install_malloc_and_free_hooks(on_allocation, on_free);

}  // namespace
#else
// The malloc family and every replaceable form of operator new counted here: glibc's own
// entry points, so the hooks can count and forward.
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

namespace {

void* counted_new(std::size_t size) {
  count(size);
  void* pointer = __libc_malloc(size == 0 ? 1 : size);
  if (pointer == nullptr) throw std::bad_alloc();
  return pointer;
}

void* counted_aligned_new(std::size_t size, std::align_val_t alignment) {
  count(size);
  void* pointer = __libc_memalign(static_cast<std::size_t>(alignment), size == 0 ? 1 : size);
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
void operator delete(void* pointer) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, const std::nothrow_t&) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, const std::nothrow_t&) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, std::size_t) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, std::size_t) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, std::align_val_t) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, std::align_val_t) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, std::align_val_t, const std::nothrow_t&) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, std::align_val_t, const std::nothrow_t&) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, std::size_t, std::align_val_t) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, std::size_t, std::align_val_t) noexcept { __libc_free(pointer); }
#endif

namespace nav::testing {

AllocationGuard::AllocationGuard()
    : start_allocations_(g_allocations.load(std::memory_order_seq_cst)),
      start_bytes_(g_bytes.load(std::memory_order_seq_cst)) {
#if defined(NAV_ALLOCATION_GUARD_SANITIZER_HOOKS)
  if (g_sanitizer_hooks == 0) {  // a guard that counts nothing would pass every test it is in
    std::fputs("AllocationGuard: the sanitizer runtime refused the allocation hooks\n", stderr);
    std::abort();
  }
#endif
}

AllocationGuard::~AllocationGuard() = default;

std::size_t AllocationGuard::allocations() const {
  return g_allocations.load(std::memory_order_seq_cst) - start_allocations_;
}

std::size_t AllocationGuard::bytes() const { return g_bytes.load(std::memory_order_seq_cst) - start_bytes_; }

}  // namespace nav::testing
