#pragma once
//! An allocator whose resize() leaves new elements of trivial types uninitialised (default-
//! initialised) instead of zeroing them: for scratch arrays that are resized to a bound and
//! then filled, such as the pair list, which each rebuild grows to twice its worst case and
//! cuts back to what it found (zeroing it was a measurable cost in dense runs; see docs/dev/performance.md).
#include <memory>
#include <new>
#include <utility>

namespace hardsphere::detail {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(noexcept(::new (static_cast<void*>(p)) U)) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

}  // namespace hardsphere::detail
