// SPDX-License-Identifier: MIT
#pragma once
// Items packed into per-cell lists (private to core): the spatial index's faces per cell and the
// clustering's points per cell, and the prefix sum they and the clustering's rows use. Every
// whole-array pass runs over the pool, so the calling thread runs none over the items or cells.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
#include "parallel_beside.h"
#include "uninit_vector.h"

namespace deepcut::detail {

/// An exclusive prefix sum over the pool: calls put(i, sum of count(j) for j < i) for every i in
/// [0, n) and returns the total. count(i) is read before put(i) (so both may use one slot) and
/// never after. In blocks: each block's total, the totals summed serially (one per block), then
/// each block's sums. The sums are taken in 64 bits: a total past UINT32_MAX throws
/// Error{InvalidArgument} before any put (the offsets, and the arrays they index, are 32-bit).
template <class Count, class Put>
std::uint32_t exclusive_scan(std::size_t n, Count&& count, Put&& put) {
  constexpr std::size_t kBlock = 1 << 16;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::uint64_t> base(blocks + 1, 0);
  parallel_for(blocks, 1, [&](std::size_t b, std::size_t) {
    std::uint64_t sum = 0;
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) sum += count(i);
    base[b + 1] = sum;
  });
  for (std::size_t b = 0; b < blocks; ++b) base[b + 1] += base[b];
  if (base[blocks] > UINT32_MAX)
    throw Error(ErrorCode::InvalidArgument,
                "packed lists: " + std::to_string(base[blocks]) + " entries, more than 32-bit offsets hold");
  parallel_for(blocks, 1, [&](std::size_t b, std::size_t) {
    auto at = static_cast<std::uint32_t>(base[b]);
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
      const std::uint32_t c = count(i);
      put(i, at);
      at += c;
    }
  });
  return static_cast<std::uint32_t>(base[blocks]);
}

/// Sorts [first, last): by insertion when short (a cell lists a few items; std::sort's call and
/// set-up cost more than sorting them), else std::sort.
inline void sort_short(std::uint32_t* first, std::uint32_t* last) {
  if (last - first > 16) return std::sort(first, last);
  for (std::uint32_t* i = first + (first != last); i < last; ++i)
    for (std::uint32_t* j = i; j > first && j[0] < j[-1]; --j) std::swap(j[0], j[-1]);
}

/// fill_csr for few cells: a count per chunk and cell, their prefix sum in cell order (chunks in
/// order within a cell), then each chunk files its items from its own offsets. No atomics and
/// no sort: every cell lists its items in increasing order by construction.
template <class CellsOf>
void fill_csr_by_chunk(std::size_t n, std::size_t cells, std::size_t grain, std::vector<std::uint32_t>& start,
                       std::vector<std::uint32_t>& items, CellsOf&& cells_of) {
  const std::size_t chunks = (n + grain - 1) / grain;
  std::vector<std::uint32_t> at(chunks * cells,
                                0);  // chunk k's count, then offset, in cell c: at[k * cells + c]
  parallel_for(n, grain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* mine = at.data() + (b / grain) * cells;
    for (std::size_t i = b; i < e; ++i) cells_of(i, [&](std::size_t c) { ++mine[c]; });
  });
  auto slot = [&](std::size_t j) -> std::uint32_t& { return at[(j % chunks) * cells + j / chunks]; };
  resize_prefaulted(start, cells + 1, std::uint32_t(0));
  const std::uint32_t total = exclusive_scan(
      chunks * cells, [&](std::size_t j) { return slot(j); },
      [&](std::size_t j, std::uint32_t offset) {
        if (j % chunks == 0) start[j / chunks] = offset;
        slot(j) = offset;
      });
  start[cells] = total;
  resize_prefaulted(items, std::size_t(total), std::uint32_t(0));
  parallel_for(n, grain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* mine = at.data() + (b / grain) * cells;
    for (std::size_t i = b; i < e; ++i)
      cells_of(i, [&](std::size_t c) { items[mine[c]++] = static_cast<std::uint32_t>(i); });
  });
}

/// fill_csr for many cells: fill_csr_by_chunk's scheme over buckets of 2^shift consecutive cells
/// (a count per chunk and bucket, their prefix sum in bucket order, then each chunk files its
/// items from its own offsets, each with its cell within the bucket: every bucket's range lists
/// its items in increasing order, at the slots its cells' lists take in `items`), then each
/// bucket's range put in cell order into `items` by a counting sort that keeps their order. No
/// atomics and no comparison sort, and each pass works on a chunk's or a bucket's own small
/// arrays. `start` and `items` are sized (a serial fill each) beside the two passes over the
/// items. Needs shift <= 16.
template <class CellsOf>
void fill_csr_by_bucket(std::size_t n, std::size_t cells, std::size_t grain, unsigned shift,
                        std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items, CellsOf&& cells_of) {
  const std::size_t chunks = (n + grain - 1) / grain;
  const std::size_t width = std::size_t(1) << shift;
  const std::size_t buckets = (cells + width - 1) >> shift;
  // Chunk k's count, then offset, in bucket b: at[k * buckets + b]; each chunk clears its own row.
  UninitVector<std::uint32_t> at(chunks * buckets);
  reserve_prefaulted(start, cells + 1, 0);
  parallel_for_beside(
      n, grain,
      [&](std::size_t b, std::size_t e) {
        std::uint32_t* mine = at.data() + (b / grain) * buckets;
        std::fill(mine, mine + buckets, 0u);
        for (std::size_t i = b; i < e; ++i) cells_of(i, [&](std::size_t c) { ++mine[c >> shift]; });
      },
      [&] { start.resize(cells + 1); });
  std::vector<std::uint32_t> first(buckets + 1);  // each bucket's first slot
  auto slot = [&](std::size_t j) -> std::uint32_t& { return at[(j % chunks) * buckets + j / chunks]; };
  const std::uint32_t total = exclusive_scan(
      chunks * buckets, [&](std::size_t j) { return slot(j); },
      [&](std::size_t j, std::uint32_t offset) {
        if (j % chunks == 0) first[j / chunks] = offset;
        slot(j) = offset;
      });
  first[buckets] = total;
  // The items by bucket, and each one's cell within its bucket.
  UninitVector<std::uint32_t> filed(total);
  UninitVector<std::uint16_t> local(total);
  prefault(filed.data(), filed.size() * sizeof(std::uint32_t));
  prefault(local.data(), local.size() * sizeof(std::uint16_t));
  reserve_prefaulted(items, total, 0);
  parallel_for_beside(
      n, grain,
      [&](std::size_t b, std::size_t e) {
        std::uint32_t* mine = at.data() + (b / grain) * buckets;
        for (std::size_t i = b; i < e; ++i)
          cells_of(i, [&](std::size_t c) {
            const std::uint32_t k = mine[c >> shift]++;
            filed[k] = static_cast<std::uint32_t>(i);
            local[k] = static_cast<std::uint16_t>(c & (width - 1));
          });
      },
      [&] { items.resize(total); });
  start[cells] = total;
  parallel_for(buckets, 4, [&](std::size_t b0, std::size_t b1) {
    std::vector<std::uint32_t> cursor(width);
    for (std::size_t b = b0; b < b1; ++b) {
      const std::uint32_t s = first[b], e = first[b + 1];
      const std::size_t c0 = b << shift, w = std::min(cells - c0, width);
      std::fill(cursor.begin(), cursor.begin() + w, 0u);
      for (std::uint32_t k = s; k < e; ++k) ++cursor[local[k]];
      std::uint32_t run = s;
      for (std::size_t l = 0; l < w; ++l) {
        const std::uint32_t count = cursor[l];
        start[c0 + l] = run;
        cursor[l] = run;
        run += count;
      }
      for (std::uint32_t k = s; k < e; ++k) items[cursor[local[k]]++] = filed[k];
    }
  });
}

/// Fills `start` (cells + 1 offsets) and `items` (cell c lists items[start[c] .. start[c + 1]))
/// from cells_of(i, visit), which calls visit(cell) for each cell item i in [0, n) goes to.
/// Every cell lists its items in increasing order, whatever the thread count: for few cells (a
/// count per chunk and cell costs no more than the items) by fill_csr_by_chunk, for more by
/// fill_csr_by_bucket; only past 2^16 cells per bucket (a count per chunk and bucket of 65536
/// cells outnumbering the items) with atomic cursors, on several threads each cell's list
/// sorted after.
/// `start` and `items` must be empty.
template <class CellsOf>
void fill_csr(std::size_t n, std::size_t cells, std::vector<std::uint32_t>& start,
              std::vector<std::uint32_t>& items, CellsOf&& cells_of) {
  constexpr std::size_t kGrain = 1 << 15;
  if ((n + kGrain - 1) / kGrain * cells <= std::max<std::size_t>(n, kGrain))
    return fill_csr_by_chunk(n, cells, kGrain, start, items, cells_of);
  // Buckets of 4096 cells (fewer when that leaves under 512 buckets for the pool to share),
  // wider while the counts per chunk and bucket would outnumber the items.
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  auto buckets = [cells](unsigned s) { return (cells + (std::size_t(1) << s) - 1) >> s; };
  unsigned shift = 12;
  while (shift > 6 && buckets(shift) < 512) --shift;
  while (shift < 16 && chunks * buckets(shift) > std::max(n, kGrain)) ++shift;
  if (chunks * buckets(shift) <= std::max(n, kGrain))
    return fill_csr_by_bucket(n, cells, kGrain, shift, start, items, cells_of);
  using Cursor = std::atomic<std::uint32_t>;
  std::unique_ptr<Cursor[]> cursor(new Cursor[cells]);
  parallel_for(cells, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) cursor[c].store(0, std::memory_order_relaxed);
  });
  // On one thread the chunks run in order: plain increments, and the lists come out sorted.
  const bool serial = thread_count() == 1;
  auto bump = [serial](Cursor& c) {
    if (!serial) return c.fetch_add(1, std::memory_order_relaxed);
    const std::uint32_t v = c.load(std::memory_order_relaxed);
    c.store(v + 1, std::memory_order_relaxed);
    return v;
  };
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) cells_of(i, [&](std::size_t c) { bump(cursor[c]); });
  });
  // Each cell's start; its cursor moves there.
  resize_prefaulted(start, cells + 1, std::uint32_t(0));
  const std::uint32_t total = exclusive_scan(
      cells, [&](std::size_t c) { return cursor[c].load(std::memory_order_relaxed); },
      [&](std::size_t c, std::uint32_t at) {
        start[c] = at;
        cursor[c].store(at, std::memory_order_relaxed);
      });
  start[cells] = total;
  resize_prefaulted(items, std::size_t(total), std::uint32_t(0));
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      cells_of(i, [&](std::size_t c) { items[bump(cursor[c])] = static_cast<std::uint32_t>(i); });
  });
  if (serial) return;
  parallel_for(cells, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) sort_short(items.data() + start[c], items.data() + start[c + 1]);
  });
}

}  // namespace deepcut::detail
