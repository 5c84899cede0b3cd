// SPDX-License-Identifier: MIT
#include "posed_checks.h"

#include <sstream>

namespace deepcut::test {
namespace {

std::string where(const std::pair<int, int>& key, const std::string& what) {
  std::ostringstream out;
  out << "node " << key.first << " primitive " << key.second << ": " << what;
  return out.str();
}

template <typename T, typename A>
std::string first_differing(const std::vector<T, A>& got, const std::vector<T, A>& want, const char* what) {
  if (got.size() != want.size()) return std::string(what) + " count differs";
  for (std::size_t i = 0; i < want.size(); ++i)
    if (!(got[i] == want[i])) return std::string(what) + " " + std::to_string(i) + " differs";
  return {};
}

std::string instance_difference(const PosedMesh& got, const PosedMesh& want) {
  if (got.mesh != want.mesh) return "mesh differs";
  for (const std::string& d : {first_differing(got.posed, want.posed, "posed position"),
                               first_differing(got.linear, want.linear, "linear map"),
                               first_differing(got.weights, want.weights, "morph weight")})
    if (!d.empty()) return d;
  if (!(got.bounds.min == want.bounds.min && got.bounds.max == want.bounds.max)) return "bounds differ";
  if (got.gridless || want.gridless) return {};
  if (got.grid.face_count() != want.grid.face_count()) return "grid face count differs";
  if (got.grid.query_box(want.bounds) != want.grid.query_box(want.bounds)) return "grid answer over the bounds differs";
  return {};
}

}  // namespace

std::string posed_model_difference(const PosedModel& got, const PosedModel& fresh) {
  if (got.size() != fresh.size()) return "instance count differs";
  for (const auto& [key, want] : fresh.instances()) {
    const PosedMesh* mine = got.find(key.first, key.second);
    if (mine == nullptr) return where(key, "missing");
    const std::string d = instance_difference(*mine, want);
    if (!d.empty()) return where(key, d);
  }
  return {};
}

std::string difference_from_fresh_build(const PosedModel& got, const Model& model) {
  return posed_model_difference(got, PosedModel::build(model, got.key()));
}

}  // namespace deepcut::test
