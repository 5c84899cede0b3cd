// SPDX-License-Identifier: MIT
#pragma once
// Sizing several big lists at once (the cut's side lists, model surgery's split lists). Private
// to core.

#include <cstddef>
#include <vector>

#include "deepcut/core/parallel.h"

namespace deepcut::detail {

/// Lists list(0) .. list(count - 1) (distinct) resized to size(i), with room for extra_room more:
/// each list's room is reserved here, on the calling thread (its heap, so the memory comes from
/// the caller's arena whichever thread fills it), then the lists are resized side by side, a
/// list a task over the pool (run_chunks): a resize value-initialises the new entries, a fill
/// that faults in fresh pages, which the tasks share instead of the calling thread taking them
/// one after the other.
template <class ListAt, class SizeAt>
void size_side_by_side(std::size_t count, const ListAt& list, const SizeAt& size,
                       std::size_t extra_room = 0) {
  for (std::size_t i = 0; i < count; ++i) list(i).reserve(size(i) + extra_room);
  run_chunks(count, [&](std::size_t i) { list(i).resize(size(i)); });  // in its room: no allocation
}

}  // namespace deepcut::detail
