// SPDX-License-Identifier: MIT
#include "deepcut/core/process_memory.h"

#include <climits>

#if defined(__GLIBC__)
#include <malloc.h>
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

}  // namespace deepcut
