// SPDX-License-Identifier: MIT
#include "deepcut/core/weld.h"

#include <cstring>
#include <unordered_map>
#include <vector>

namespace deepcut {
namespace {

struct VertexBytes {
  const SurfaceMesh& mesh;
  std::vector<const AttributeArrayBase*> arrays;

  explicit VertexBytes(const SurfaceMesh& m) : mesh(m) {
    for (const auto& name : m.vertex_attrs().names()) arrays.push_back(m.vertex_attrs().base(name));
  }
  // Positions hash with -0 folded into +0 so they weld; other attributes hash raw.
  std::uint64_t hash(std::uint32_t v, bool position_only) const {
    std::uint64_t h = 1469598103934665603ull;
    const glm::vec3 p = mesh.positions()[v] + glm::vec3(0.0f);
    const auto* pb = reinterpret_cast<const unsigned char*>(&p);
    for (std::size_t i = 0; i < sizeof(p); ++i) h = (h ^ pb[i]) * 1099511628211ull;
    if (position_only) return h;
    for (const auto* a : arrays) {
      if (a == mesh.vertex_attrs().base(attr::kPosition)) continue;
      const auto* b = static_cast<const unsigned char*>(a->element_data(v));
      for (std::size_t i = 0; i < a->element_bytes(); ++i) h = (h ^ b[i]) * 1099511628211ull;
    }
    return h;
  }
  bool equal(std::uint32_t u, std::uint32_t v) const {
    if (mesh.positions()[u] != mesh.positions()[v]) return false;  // -0 == +0 here
    for (const auto* a : arrays) {
      if (a == mesh.vertex_attrs().base(attr::kPosition)) continue;
      if (std::memcmp(a->element_data(u), a->element_data(v), a->element_bytes()) != 0) return false;
    }
    return true;
  }
};

}  // namespace

WeldReport weld(SurfaceMesh& mesh) {
  WeldReport report;
  const VertexBytes bytes(mesh);
  const auto nv = static_cast<std::uint32_t>(mesh.vertex_count());
  std::vector<std::uint32_t> to_new(nv, kInvalidIndex);
  std::vector<std::uint32_t> keep;  // new vertex -> old representative
  keep.reserve(nv);
  std::unordered_multimap<std::uint64_t, std::uint32_t> seen;  // hash -> new vertex
  std::unordered_map<std::uint64_t, std::uint32_t> at_position;
  seen.reserve(nv);
  std::vector<Triangle> faces;
  std::vector<std::uint32_t> kept_faces, corners;
  faces.reserve(mesh.face_count());
  auto map = [&](VertexId v) {
    std::uint32_t& slot = to_new[v.index];
    if (slot != kInvalidIndex) return VertexId(slot);
    const auto h = bytes.hash(v.index, false);
    auto range = seen.equal_range(h);
    for (auto it = range.first; it != range.second; ++it)
      if (bytes.equal(keep[it->second], v.index)) {
        slot = it->second;
        ++report.merged;
        return VertexId(slot);
      }
    slot = static_cast<std::uint32_t>(keep.size());
    keep.push_back(v.index);
    seen.emplace(h, slot);
    if (!at_position.emplace(bytes.hash(v.index, true), slot).second) ++report.kept_apart;
    return VertexId(slot);
  };
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    faces.push_back({map(t[0]), map(t[1]), map(t[2])});
    kept_faces.push_back(f.index);
    for (int k = 0; k < 3; ++k) corners.push_back(SurfaceMesh::corner(f, k));
  });
  for (std::uint32_t v = 0; v < nv; ++v) report.dropped += to_new[v] == kInvalidIndex;
  AttributeSet vattrs = mesh.vertex_attrs(), fattrs = mesh.face_attrs(), cattrs = mesh.corner_attrs();
  vattrs.gather(keep);
  fattrs.gather(kept_faces);
  cattrs.gather(corners);
  mesh.assign(std::move(faces), std::move(vattrs), std::move(fattrs), std::move(cattrs));
  return report;
}

}  // namespace deepcut
