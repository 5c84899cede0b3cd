// SPDX-License-Identifier: MIT
#include "io/import_problems.h"

#include <algorithm>

namespace deepcut::io_detail {

void add_problem(std::vector<ImportProblem>& problems, const std::string& kind, std::size_t count, const Counted& what,
                 const std::string& place) {
  if (count == 0) return;
  auto it = std::find_if(problems.begin(), problems.end(), [&](const ImportProblem& p) { return p.kind == kind; });
  if (it == problems.end()) {
    problems.push_back({kind, "", 0, {}});
    it = problems.end() - 1;
  }
  it->count += count;
  if (!place.empty() && std::find(it->places.begin(), it->places.end(), place) == it->places.end())
    it->places.push_back(place);
  std::string message = std::to_string(it->count) + " " + (it->count == 1 ? what.one : what.many);
  const std::size_t shown = std::min(it->places.size(), kShownPlaces);
  for (std::size_t i = 0; i < shown; ++i) message += (i == 0 ? ": " : ", ") + it->places[i];
  if (it->places.size() > shown) message += " and " + std::to_string(it->places.size() - shown) + " more";
  it->message = std::move(message);
}

}  // namespace deepcut::io_detail
