#pragma once
// Counts heap allocations made by any thread inside a scope, so that tests can prove
// that step functions never allocate. Linked into every test program: it replaces the
// global operator new/delete and malloc/calloc/realloc/free or, in sanitizer builds, hooks
// into the sanitizer's allocator.
#include <cstddef>

namespace nav::testing {

/// While alive, counts every heap allocation (operator new in all its forms and the malloc
/// family). Guards nest; each sees the allocations of its own scope.
class AllocationGuard {
 public:
  AllocationGuard();
  ~AllocationGuard();
  AllocationGuard(const AllocationGuard&) = delete;
  AllocationGuard& operator=(const AllocationGuard&) = delete;

  /// Allocations (new, malloc, calloc, realloc, aligned forms) since construction.
  std::size_t allocations() const;
  /// Bytes requested by those allocations.
  std::size_t bytes() const;

 private:
  std::size_t start_allocations_;
  std::size_t start_bytes_;
};

}  // namespace nav::testing
