// SPDX-License-Identifier: MIT
#pragma once
// Recording what an importer repaired or dropped (private to core): one `ImportProblem` per kind,
// its count summed and its places listed, its message rewritten from the totals, so a file with
// the same repair in forty primitives still says it in one line.

#include <string>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut::io_detail {

// A phrase that follows a count, in the singular and the plural:
// {"vertex had weights not summing to 1", "vertices had weights not summing to 1"}.
struct Counted {
  std::string one;
  std::string many;
};

// Adds `count` things of `kind` at `place` ("" for the whole file; places are listed once each)
// to `problems`, joining the entry of that kind or starting one (nothing when `count` is 0). The message is
// "<total> <phrase>: <place>, <place>, ... and N more" (at most kShownPlaces places named).
void add_problem(std::vector<ImportProblem>& problems, const std::string& kind, std::size_t count, const Counted& what,
                 const std::string& place = "");

inline constexpr std::size_t kShownPlaces = 4;

}  // namespace deepcut::io_detail
