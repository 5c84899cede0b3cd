// SPDX-License-Identifier: MIT
#include "deepcut/core/process_memory.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <vector>

#if defined(__GLIBC__)
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>
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

// Whether the page holding `p` is resident (mincore).
bool resident(const void* p) {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  unsigned char in = 0;
  EXPECT_EQ(mincore(reinterpret_cast<void*>(reinterpret_cast<std::uintptr_t>(p) / page * page), 1, &in), 0);
  return (in & 1) != 0;
}

// The room of an array past the elements kept leaves the resident set, whole pages only: the
// elements, the capacity and the page holding the last kept element stay; growing back into the
// room gives the values written then.
TEST(ProcessMemory, ReleasedRoomLeavesTheResidentSetAndKeepsTheElements) {
  std::vector<std::uint32_t> array(std::size_t(4) << 20);
  for (std::size_t i = 0; i < array.size(); ++i) array[i] = static_cast<std::uint32_t>(i);
  const std::size_t capacity = array.capacity(), keep = 100000;
  array.resize(1000);
  const std::size_t released = deepcut::release_room(array, keep);
  EXPECT_GT(released, (capacity - keep) * sizeof(std::uint32_t) - 2 * 4096);
  EXPECT_LE(released, (capacity - keep) * sizeof(std::uint32_t));
  EXPECT_EQ(array.capacity(), capacity);
  EXPECT_TRUE(resident(array.data() + keep - 1));
  EXPECT_FALSE(resident(array.data() + keep + 2048));
  EXPECT_FALSE(resident(array.data() + capacity - 2048));  // (the last page may hold other bytes)
  for (std::size_t i = 0; i < array.size(); ++i) ASSERT_EQ(array[i], i);
  array.resize(capacity, 7);
  EXPECT_EQ(array[capacity - 1], 7u);
  EXPECT_EQ(deepcut::release_room(array, keep), 0u);  // the size is kept at least
}
#endif

}  // namespace
