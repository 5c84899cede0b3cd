// SPDX-License-Identifier: MIT
#pragma once
// Items packed into per-cell lists (private to core): the spatial index's faces per cell and the
// clustering's points per cell, and the prefix sum they and the clustering's rows use. Every
// whole-array pass runs over the pool, so the calling thread runs none over the items or cells.

#include <algorithm>
#include <cstdint>
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

/// Puts the range [s, e) of a bucket of `w` cells from cell c0, filed in item order with each
/// item's cell within the bucket in local[k], into `items` in cell order (a counting sort that
/// keeps their order), and sets the cells' starts. `cursor` holds at least w counts.
inline void sort_bucket(std::uint32_t s, std::uint32_t e, std::size_t c0, std::size_t w,
                        const std::uint32_t* filed, const std::uint16_t* local, std::uint32_t* cursor,
                        std::uint32_t* start, std::uint32_t* items) {
  std::fill(cursor, cursor + w, 0u);
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

/// fill_csr over buckets of 2^shift consecutive cells: a count per chunk and bucket, their
/// prefix sum in bucket order, then each chunk files its items from its own offsets (every
/// bucket's range lists its items in increasing order, at the slots its cells' lists take in
/// `items`). With shift 0 a bucket is a cell: the sums are the cells' starts and the chunks file
/// straight into `items`. Else each chunk files with each item its cell within the bucket, and
/// each bucket's range is put in cell order into `items` by sort_bucket. No atomics and no
/// comparison sort, and each pass works on a chunk's or a bucket's own small arrays. `start`
/// (and, for shift > 0, `items`) is sized (a serial fill) beside a pass over the items. Needs
/// shift <= 16.
template <class CellsOf>
void fill_csr_by_bucket(std::size_t n, std::size_t cells, std::size_t grain, unsigned shift,
                        std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items,
                        CellsOf&& cells_of) {
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
  // Each bucket's first slot: the cells' starts themselves for shift 0.
  std::vector<std::uint32_t> first_of_bucket(shift == 0 ? 0 : buckets + 1);
  std::uint32_t* first = shift == 0 ? start.data() : first_of_bucket.data();
  auto slot = [&](std::size_t j) -> std::uint32_t& { return at[(j % chunks) * buckets + j / chunks]; };
  const std::uint32_t total = exclusive_scan(
      chunks * buckets, [&](std::size_t j) { return slot(j); },
      [&](std::size_t j, std::uint32_t offset) {
        if (j % chunks == 0) first[j / chunks] = offset;
        slot(j) = offset;
      });
  first[buckets] = total;
  if (shift == 0) {
    resize_prefaulted(items, std::size_t(total), std::uint32_t(0));
    parallel_for(n, grain, [&](std::size_t b, std::size_t e) {
      std::uint32_t* mine = at.data() + (b / grain) * buckets;
      for (std::size_t i = b; i < e; ++i)
        cells_of(i, [&](std::size_t c) { items[mine[c]++] = static_cast<std::uint32_t>(i); });
    });
    return;
  }
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
      const std::size_t c0 = b << shift;
      sort_bucket(first[b], first[b + 1], c0, std::min(cells - c0, width), filed.data(), local.data(),
                  cursor.data(), start.data(), items.data());
    }
  });
}

/// Fills `start` (cells + 1 offsets) and `items` (cell c lists items[start[c] .. start[c + 1]))
/// from cells_of(i, visit), which calls visit(cell) for each cell item i in [0, n) goes to.
/// Every cell lists its items in increasing order, whatever the thread count, by
/// fill_csr_by_bucket: buckets of one cell where a count per chunk and cell costs no more than
/// the items, else of 2^6 to 2^16 cells. Any cell count works: past 2^16 cells per bucket
/// (only above about 2^31 cells, which the callers never reach in practice: the spatial index's
/// grid_cell keeps about one cell per face unless the model is very flat, the point grid caps
/// its cells at max(4096, 2n), the clustering has fewer particles than vertices) the counts per
/// chunk and bucket outnumber the items, yet they take chunks / 65536 words per cell, less than
/// a cursor per cell would. More than UINT32_MAX (item, cell) pairs throw Error{InvalidArgument}
/// (exclusive_scan), before `items` is sized. `start` and `items` must be empty.
template <class CellsOf>
void fill_csr(std::size_t n, std::size_t cells, std::vector<std::uint32_t>& start,
              std::vector<std::uint32_t>& items, CellsOf&& cells_of) {
  constexpr std::size_t kGrain = 1 << 15;
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  const std::size_t limit = std::max(n, kGrain);
  if (chunks * cells <= limit) return fill_csr_by_bucket(n, cells, kGrain, 0, start, items, cells_of);
  // Buckets of 4096 cells (fewer when that leaves under 512 buckets for the pool to share),
  // wider while the counts per chunk and bucket would outnumber the items.
  auto buckets = [cells](unsigned s) { return (cells + (std::size_t(1) << s) - 1) >> s; };
  unsigned shift = 12;
  while (shift > 6 && buckets(shift) < 512) --shift;
  while (shift < 16 && chunks * buckets(shift) > limit) ++shift;
  fill_csr_by_bucket(n, cells, kGrain, shift, start, items, cells_of);
}

}  // namespace deepcut::detail
