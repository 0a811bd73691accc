// qrm/backends/detail/aligned_allocator.hpp: storage for large states, aligned to 2 MiB and marked for
// transparent huge pages where the system offers them. Gates that stride through a big state
// (high controls, high targets) otherwise miss the TLB on nearly every access.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

namespace qrm::detail {

template <class T>
struct huge_page_allocator {
  using value_type = T;
  static constexpr std::size_t huge = std::size_t{2} << 20;

  huge_page_allocator() = default;
  template <class U>
  huge_page_allocator(const huge_page_allocator<U>&) {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < huge) {
      return static_cast<T*>(::operator new(bytes, std::align_val_t{64}));
    }
    const std::size_t rounded = (bytes + huge - 1) / huge * huge;
    void* p = std::aligned_alloc(huge, rounded);
    if (!p) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE) && !defined(QRM_NO_HUGE_PAGES)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint; ignored where unsupported
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) < huge)
      ::operator delete(p, std::align_val_t{64});
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const huge_page_allocator<U>&) const {
    return true;
  }
};

}  // namespace qrm::detail
