// SPDX-License-Identifier: MIT
#include "deepcut/core/process_memory.h"

#include <climits>
#include <cstdint>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace deepcut {

bool keep_freed_memory() {
#if defined(__GLIBC__)
  constexpr int kLargestFromHeap = 1 << 30;  // larger blocks are still mapped and unmapped alone
  const bool kept = ::mallopt(M_MMAP_THRESHOLD, kLargestFromHeap) == 1;
  return ::mallopt(M_TRIM_THRESHOLD, INT_MAX) == 1 && kept;
#else
  return false;
#endif
}

void release_freed_memory() {
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

std::size_t release_pages(void* begin, void* end) noexcept {
#if defined(__linux__)
  const detail::PageSpan pages = detail::inner_pages(begin, end);
  if (begin == nullptr || pages.last == pages.first) return 0;
  const std::size_t bytes = pages.last - pages.first;
  return ::madvise(reinterpret_cast<void*>(pages.first), bytes, MADV_DONTNEED) == 0 ? bytes : 0;
#else
  (void)begin;
  (void)end;
  return 0;
#endif
}

namespace detail {

PageSpan inner_pages(const void* begin, const void* end) noexcept {
#if defined(__linux__)
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
#else
  constexpr std::uintptr_t page = 4096;  // (no call on pages uses it there)
#endif
  const std::uintptr_t first = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) / page * page;
  const std::uintptr_t last = reinterpret_cast<std::uintptr_t>(end) / page * page;
  return {first, last > first ? last : first};
}

}  // namespace detail

}  // namespace deepcut
