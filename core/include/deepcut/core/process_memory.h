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

namespace deepcut {

/// Keeps freed memory in the process for later allocations (glibc: blocks up to 1 GiB come from
/// the heap, and the heap is never trimmed). Call once at the start of `main`, before any thread
/// starts. Returns false where the C library has no such setting (nothing changes there).
bool keep_freed_memory();

}  // namespace deepcut
