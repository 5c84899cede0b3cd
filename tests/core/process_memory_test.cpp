// SPDX-License-Identifier: MIT
#include "deepcut/core/process_memory.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <vector>

#if defined(__GLIBC__)
#include <sys/resource.h>
#endif
#if defined(__GLIBC__) || defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace {

#if defined(__GLIBC__) || defined(__linux__)
std::size_t page_bytes() { return static_cast<std::size_t>(sysconf(_SC_PAGESIZE)); }
#endif

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
  for (std::size_t i = 0; i < bytes; i += page_bytes()) data[i] = 1;
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
  const long pages = static_cast<long>(kBytes / page_bytes());
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
  EXPECT_GT(kept - resident_pages(), static_cast<long>(kBytes / page_bytes() / 2)) << "pages given back";
}
#endif

#if defined(__linux__)
// Whether the page holding `p` is resident (mincore).
bool resident(const void* p) {
  const std::uintptr_t page = page_bytes();
  unsigned char in = 0;
  EXPECT_EQ(mincore(reinterpret_cast<void*>(reinterpret_cast<std::uintptr_t>(p) / page * page), 1, &in), 0);
  return (in & 1) != 0;
}

// The room of an array past the elements kept leaves the resident set, whole pages only: the
// elements, the capacity and the page holding the last element stay. Asked to keep fewer
// elements than the array holds (200000, keep 100000), it keeps them all.
TEST(ProcessMemory, ReleasedRoomLeavesTheResidentSetAndKeepsTheElements) {
  std::vector<std::uint32_t> array(std::size_t(4) << 20);
  for (std::size_t i = 0; i < array.size(); ++i) array[i] = static_cast<std::uint32_t>(i);
  const std::size_t capacity = array.capacity(), size = 200000, keep = 100000;
  const std::size_t page = page_bytes(), per_page = page / sizeof(std::uint32_t);
  array.resize(size);
  const std::size_t released = deepcut::release_room(array, keep);
  EXPECT_GT(released, (capacity - size) * sizeof(std::uint32_t) - 2 * page);
  EXPECT_LE(released, (capacity - size) * sizeof(std::uint32_t));
  EXPECT_EQ(array.capacity(), capacity);
  EXPECT_TRUE(resident(array.data() + size - 1));
  EXPECT_FALSE(resident(array.data() + size + per_page));      // in the first whole page past them
  EXPECT_FALSE(resident(array.data() + capacity - per_page));  // in the last whole page
  for (std::size_t i = 0; i < size; ++i) ASSERT_EQ(array[i], i);
}
#endif

}  // namespace
