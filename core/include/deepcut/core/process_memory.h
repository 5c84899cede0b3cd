// SPDX-License-Identifier: MIT
#pragma once
/// @file process_memory.h
/// How the process's heap treats the memory it frees.
///
/// An operation on a 1M-triangle model frees arrays of tens of megabytes and the next operation
/// allocates arrays of the same sizes. glibc's default hands blocks over 32 MiB (and the top of
/// the heap past its trim threshold) back to the kernel on free, so the next operation takes
/// every page again as a fresh, zeroed page fault: on a virtual machine, a few microseconds each,
/// and hundreds of thousands of them per operation. `keep_freed_memory` makes the heap keep what
/// it frees for the next allocation instead: resident memory then stays at its peak (what the
/// largest model and operation needed), and an operation after the first writes into pages the
/// process already has.
///
/// The other way round, memory a live array holds past its elements: `release_pages` and
/// `release_room` hand such pages back to the system while the array keeps its capacity (a
/// piece compacted in place keeps its mesh's arrays, whose pages past the piece held the mesh's
/// elements and, with freed memory kept, would stay resident as long as the piece lives).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace deepcut {

/// Keeps freed memory in the process for later allocations (glibc: blocks up to 1 GiB come from
/// the heap, and the heap is never trimmed). Call once at the start of `main`, before any thread
/// starts. Returns false where the C library has no such setting (nothing changes there).
///
/// glibc gives each thread that allocates its own arena: a block goes back to the arena it came
/// from, whichever thread frees it, and serves only that arena's later allocations. So resident
/// memory may reach the sum of the arenas' peaks (the open's worker, the pool's threads, the UI
/// thread). Arenas other than the main one grow in 64 MiB heaps, so a block larger than that
/// made on another thread is still mapped and unmapped on its own.
bool keep_freed_memory();

/// Hands the free memory of every arena back to the system (glibc: malloc_trim). For the moment
/// a large model has been replaced: what it held and the new model did not reuse. Costs a walk
/// of the heaps; the next allocations fault their pages in again.
void release_freed_memory();

/// Hands the whole pages lying inside [begin, end) back to the system (Linux: madvise
/// MADV_DONTNEED), the block they are in staying allocated: a later write there faults in a fresh
/// zeroed page. For the room of a live array past its elements that once held data (a piece
/// compacted in place keeps its mesh's capacity, its old elements' pages written): with freed
/// memory kept (keep_freed_memory), the pages of an allocation stay resident as long as it lives,
/// whatever part of it is used. Only pages entirely inside the range are touched (the heap's own
/// bookkeeping lies outside the bytes it handed out), and those bytes must hold no object.
/// Costs one system call and time in proportion to the pages in the range (the kernel unmaps each
/// resident one; each is faulted in again when written). Allocates nothing. Returns the bytes
/// released: 0 for a range holding no whole page, where the system refuses the call (nothing is
/// known to have changed then) or has no such call (nothing changes there).
std::size_t release_pages(void* begin, void* end) noexcept;

/// release_pages over the room of `array` past its first `keep` elements (its size at least): its
/// capacity stays, and growing into that room faults the pages in again.
template <class T>
std::size_t release_room(std::vector<T>& array, std::size_t keep) noexcept {
  if (keep < array.size()) keep = array.size();
  if (keep >= array.capacity()) return 0;
  return release_pages(array.data() + keep, array.data() + array.capacity());
}

namespace detail {

/// The addresses of the whole pages lying inside [begin, end): `first` rounded up from `begin`
/// and `last` down from `end` to the system's page size, `last == first` when no whole page lies
/// there. The bounds a call on pages (madvise) takes for a range it must not spill out of.
struct PageSpan {
  std::uintptr_t first, last;
};
PageSpan inner_pages(const void* begin, const void* end) noexcept;

}  // namespace detail

}  // namespace deepcut
