// SPDX-License-Identifier: BSD-3-Clause
// An allocator for the kernel's largest per-primitive tables (whole-brain tube chunks: up to
// 10 GB read at random by every ray): blocks of 2 MiB and more are aligned to 2 MiB and marked
// for transparent huge pages, so that a ray's random reads do not also miss the TLB (Linux's
// default "madvise" mode gives huge pages only to memory that asks). Elsewhere, or for small
// blocks, it is the ordinary allocator.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace sightline
{
template <class T>
struct HugePageAllocator
{
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept // NOLINT(google-explicit-constructor)
  {
  }

  T* allocate(std::size_t n)
  {
    if (n > std::size_t(-1) / sizeof(T))
      throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage)
      return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p)
      throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE); // advice only: without it, ordinary pages
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept
  {
    if (n * sizeof(T) < kHugePage)
      ::operator delete(p);
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept
  {
    return true;
  }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept
  {
    return false;
  }
};
} // namespace sightline
