// SPDX-License-Identifier: MIT
#pragma once
/// @file flags.h
/// Per-element flags that passes over the thread pool set concurrently (relaxed atomic bytes:
/// any thread may mark any element, e.g. the vertices of its chunk's faces), then read once
/// every pass is done.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "deepcut/core/parallel.h"

namespace deepcut {

using Flags = std::unique_ptr<std::atomic<std::uint8_t>[]>;

/// `n` flags, all clear (cleared over the pool, in chunks of `grain`).
inline Flags cleared_flags(std::size_t n, std::size_t grain = 65536) {
  Flags flags(new std::atomic<std::uint8_t>[n]);
  std::atomic<std::uint8_t>* const to = flags.get();
  parallel_for(n, grain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) to[i].store(0, std::memory_order_relaxed);
  });
  return flags;
}

}  // namespace deepcut
