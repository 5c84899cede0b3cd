// SPDX-License-Identifier: MIT
#pragma once
/// @file parallel.h
/// A small fork-join thread pool (std::thread, no dependency) for the loops that touch every
/// vertex or face: vertex classification, attribute copies, weld, adjacency and grid builds,
/// posed positions and the soft-body vertex update.
///
/// Determinism: work is cut into fixed chunks of `grain` elements whose boundaries depend only
/// on the range and the grain, never on the number of threads. `parallel_for` bodies write
/// disjoint outputs; `parallel_reduce` combines the chunks' partial results in chunk order. So a
/// result is bit-identical whatever the thread count (1 included), and from run to run.
///
/// Threads: `std::thread::hardware_concurrency()` by default; the environment variable
/// `DEEPCUT_THREADS` (a positive integer) overrides it, and `set_thread_count` changes it at run
/// time. Calls made from inside a parallel body run serially on the calling thread.

#include <algorithm>
#include <cstddef>
#include <functional>
#include <vector>

namespace deepcut {

/// Threads the pool uses (the calling thread included); at least 1.
std::size_t thread_count();
/// Resizes the pool (1 = everything serial on the caller). Not to be called from a parallel body.
void set_thread_count(std::size_t threads);

namespace detail {
/// Runs `task(chunk)` for every chunk in [0, chunks), spread over the pool; returns when all
/// are done. The first exception a task throws is rethrown here (the other chunks still run).
void run_chunks(std::size_t chunks, const std::function<void(std::size_t)>& task);
}  // namespace detail

/// Calls `fn(begin, end)` on consecutive chunks of at most `grain` elements covering [0, n).
/// Ranges of at most `grain` elements run inline, without touching the pool.
template <class Fn>
void parallel_for(std::size_t n, std::size_t grain, Fn&& fn) {
  if (grain == 0) grain = 1;
  if (n <= grain) {
    if (n > 0) fn(std::size_t(0), n);
    return;
  }
  const std::size_t chunks = (n + grain - 1) / grain;
  detail::run_chunks(chunks, [&](std::size_t c) { fn(c * grain, std::min(n, (c + 1) * grain)); });
}

/// `map(begin, end)` returns a chunk's partial result; the partials are folded left to right
/// with `combine(acc, partial)`, starting from `init`.
template <class T, class Map, class Combine>
T parallel_reduce(std::size_t n, std::size_t grain, T init, Map&& map, Combine&& combine) {
  if (grain == 0) grain = 1;
  const std::size_t chunks = (n + grain - 1) / grain;
  if (chunks <= 1) return n == 0 ? init : combine(std::move(init), map(std::size_t(0), n));
  std::vector<T> partial(chunks, init);
  detail::run_chunks(chunks, [&](std::size_t c) { partial[c] = map(c * grain, std::min(n, (c + 1) * grain)); });
  T acc = std::move(init);
  for (auto& p : partial) acc = combine(std::move(acc), std::move(p));
  return acc;
}

/// A grain giving each thread about one chunk of a range of `n` elements, never less than
/// `min_grain`. Only for bodies whose result cannot depend on where chunks start (disjoint
/// writes, min / max, flags, lists joined in chunk order), since it follows the thread count.
inline std::size_t grain_per_thread(std::size_t n, std::size_t min_grain) {
  const std::size_t threads = thread_count();
  return std::max(min_grain, (n + threads - 1) / threads);
}

/// Runs independent tasks (e.g. one per attribute array) over the pool.
void parallel_invoke(const std::vector<std::function<void()>>& tasks);

}  // namespace deepcut
