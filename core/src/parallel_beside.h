// SPDX-License-Identifier: MIT
#pragma once
// A piece of serial work run beside a pass over the pool (private to core): sizing a std::vector
// (which writes every element on one thread) or copying one overlaps the chunks the other
// threads share instead of running before them.

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "deepcut/core/parallel.h"

namespace deepcut::detail {

/// Where `beside` runs against the chunks. Tests only: Shared (the default) leaves it to the
/// pool; First runs it before every chunk (as on one thread), Last after every chunk has run,
/// so that each order a pass can meet is checked whatever the timing.
enum class BesideOrder { Shared, First, Last };
inline BesideOrder beside_order_for_tests = BesideOrder::Shared;

/// Sets beside_order_for_tests for its lifetime and puts Shared back when it ends, even when
/// the pass under test throws. Tests only.
class BesideOrderForTests {
 public:
  explicit BesideOrderForTests(BesideOrder order) { beside_order_for_tests = order; }
  ~BesideOrderForTests() { beside_order_for_tests = BesideOrder::Shared; }
  BesideOrderForTests(const BesideOrderForTests&) = delete;
  BesideOrderForTests& operator=(const BesideOrderForTests&) = delete;
};

/// chunk(c) for every c in [0, chunks) and `beside()` in one pool job, `beside` first (usually
/// the calling thread takes it; a quick worker can). On one thread: `beside`, then the chunks
/// in order.
template <class Chunk, class Beside>
void run_chunks_beside(std::size_t chunks, Chunk&& chunk, Beside&& beside) {
  // One call of `chunk` in one task body (a second one, for the tests' orders, kept the
  // compiler from inlining the posing chunk's skin blend: 10% more instructions).
  const BesideOrder order = beside_order_for_tests;
  const std::size_t shared = order == BesideOrder::Shared ? 1 : 0;
  if (order == BesideOrder::First) beside();
  run_chunks(chunks + shared, [&](std::size_t c) {
    if (shared && c == 0) return static_cast<void>(beside());
    chunk(c - shared);
  });
  if (order == BesideOrder::Last) beside();
}

/// parallel_for(n, grain, fn) with `beside()` run beside the chunks (run_chunks_beside).
template <class Fn, class Beside>
void parallel_for_beside(std::size_t n, std::size_t grain, Fn&& fn, Beside&& beside) {
  if (grain == 0) grain = 1;
  run_chunks_beside((n + grain - 1) / grain,
                    [&](std::size_t c) { fn(c * grain, std::min(n, (c + 1) * grain)); }, beside);
}

/// parallel_reduce(n, grain, init, map, combine) with `beside()` run beside the chunks: the
/// partials folded left to right in chunk order, whatever the thread count.
template <class T, class Map, class Combine, class Beside>
T parallel_reduce_beside(std::size_t n, std::size_t grain, T init, Map&& map, Combine&& combine,
                         Beside&& beside) {
  if (grain == 0) grain = 1;
  std::vector<T> partial((n + grain - 1) / grain, init);
  parallel_for_beside(
      n, grain, [&](std::size_t b, std::size_t e) { partial[b / grain] = map(b, e); }, beside);
  T acc = std::move(init);
  for (auto& p : partial) acc = combine(std::move(acc), std::move(p));
  return acc;
}

}  // namespace deepcut::detail
