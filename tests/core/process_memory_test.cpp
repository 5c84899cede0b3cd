// SPDX-License-Identifier: MIT
#include "deepcut/core/process_memory.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <fstream>
#include <memory>

#if defined(__GLIBC__)
#include <sys/resource.h>
#endif

namespace {

#if defined(__GLIBC__)
long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// Allocates `bytes`, writes one byte per page (volatile, so the compiler keeps the block), frees.
void touch_block(std::size_t bytes) {
  std::unique_ptr<char[]> block(new char[bytes]);
  volatile char* data = block.get();
  for (std::size_t i = 0; i < bytes; i += 4096) data[i] = 1;
}

// A block over glibc's largest dynamic mmap threshold (32 MiB) is unmapped on free by default,
// so touching one again faults on every page; with freed memory kept, the second block is the
// first one's pages.
TEST(ProcessMemory, AFreedLargeBlockIsReusedWithoutPageFaults) {
  ASSERT_TRUE(deepcut::keep_freed_memory());
  constexpr std::size_t kBytes = std::size_t(64) << 20;
  touch_block(kBytes);
  const long before = minor_faults();
  touch_block(kBytes);
  const long pages = static_cast<long>(kBytes / 4096);
  EXPECT_LT(minor_faults() - before, pages / 100) << "of " << pages << " pages";
}

long resident_pages() {
  std::ifstream in("/proc/self/statm");
  long size = 0, resident = 0;
  in >> size >> resident;
  return resident;
}

// What is kept is given back on request: a freed 64 MiB block leaves the resident set.
TEST(ProcessMemory, ReleasedMemoryLeavesTheResidentSet) {
  ASSERT_TRUE(deepcut::keep_freed_memory());
  constexpr std::size_t kBytes = std::size_t(64) << 20;
  touch_block(kBytes);
  const long kept = resident_pages();
  deepcut::release_freed_memory();
  EXPECT_GT(kept - resident_pages(), static_cast<long>(kBytes / 4096 / 2)) << "pages given back";
}
#endif

}  // namespace
