// SPDX-License-Identifier: MIT
#pragma once
// Working lists a thread keeps from call to call (ear clipping's corner lists, the drill's
// plans): a small call then runs without allocating, while a list grown past a bound by a big
// call gives its memory back when that call ends, so a big call's memory does not stay with the
// thread (e.g. the studio's UI thread). One rule and one unit (bytes of capacity) for all of
// them; each owner picks its bound. Private to core.

#include <cstddef>
#include <vector>

namespace deepcut::detail {

/// Frees `list`'s memory when its capacity holds more than `kept_bytes`; a smaller list keeps
/// it (its contents are left as they are). Each list is judged on its own, so a big one does not
/// take the small ones' memory with it.
template <class T>
void give_back_if_big(std::vector<T>& list, std::size_t kept_bytes) {
  if (list.capacity() * sizeof(T) > kept_bytes) std::vector<T>().swap(list);
}

}  // namespace deepcut::detail
