// SPDX-License-Identifier: MIT
// The faces near the cylinder, and old vertices a hair from its side slid onto it (the stages of
// the rim insertion before any edge is split).
#include <algorithm>
#include <array>
#include <cmath>

#include "deepcut/core/parallel.h"
#include "ops/common/vertex_slots.h"
#include "ops/drill/rim_insertion.h"

namespace deepcut::drill {
namespace {

// Fewest faces of the grid's answer judged per parallel chunk.
constexpr std::size_t kMinCandidateGrain = 512;

}  // namespace

std::vector<FaceId> find_candidates(const SurfaceMesh& mesh, const CylinderFrame& cyl,
                                    const PosedOverlay& posed, const TriangleGrid& index) {
  std::vector<FaceId> candidates;
  const double eps = cyl.eps;
  // Far enough to hold every face around a vertex snap_shallow_vertices may move.
  const double reach =
      cyl.r + std::max(2.0 * eps, (kSnapBand + 0.01) * 2.0 * cyl.r * std::sin(geometry::kPi / cyl.samples));
  auto near_axis = [&](const Triangle& t) {
    const glm::dvec3 p0 = posed(t[0]), p1 = posed(t[1]), p2 = posed(t[2]);
    const glm::dvec3 c = (p0 + p1 + p2) / 3.0;
    const double rad =
        std::sqrt(std::max({glm::dot(p0 - c, p0 - c), glm::dot(p1 - c, p1 - c), glm::dot(p2 - c, p2 - c)}));
    const double sv = std::clamp(cyl.s(c), 0.0, cyl.len);
    const glm::dvec3 closest = cyl.a + sv * cyl.d;
    return glm::length(c - closest) <= reach + rad;
  };
  const std::vector<FaceId> near =
      index.query_capsule(glm::vec3(cyl.a), glm::vec3(cyl.a + cyl.len * cyl.d), static_cast<float>(reach));
  // Each face judged on its own (in parallel chunks), then kept in the grid's order.
  std::vector<std::uint8_t> keep(near.size(), 0);
  parallel_for(near.size(), grain_per_thread(near.size(), kMinCandidateGrain), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const FaceId f = near[i];
      keep[i] = f.index < mesh.face_slots() && !mesh.is_deleted(f) && near_axis(mesh.face(f));
    }
  });
  candidates.reserve(near.size());
  for (std::size_t i = 0; i < near.size(); ++i)
    if (keep[i]) candidates.push_back(near[i]);
  return candidates;
}

// An old vertex lying just inside (or just outside) the cylinder leaves the crossings of two of
// its edges a hair apart: the far corners of its faces fan to those two close rim points (needles
// under a degree), or it stays as the tip of a sliver between them. Such a vertex, within
// kSnapBand rim spacings of the side, is slid in its tangent plane onto the cylinder before any
// edge is split, so it becomes a rim vertex itself and its edges are not cut there. Only where
// every face around it keeps its orientation (and a non-zero area) in posed and in bind space;
// the bind position moves by the vertex's own skinning inverted (the unposer), so the edit is a
// VertexMoved in the log and the new posed position is reported (DrillResult::moved).
void snap_shallow_vertices(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed,
                           const std::vector<FaceId>& candidates) {
  const SurfaceMesh& mesh = editor.mesh();
  const int samples = cyl.samples;
  std::vector<VertexId> ring;
  std::array<std::vector<VertexId>, 2> border;  // edges ahead of / behind a vertex in its faces
  const double spacing = 2.0 * cyl.r * std::sin(geometry::kPi / samples);
  const double band = kSnapBand * spacing, close = kSnapClose * spacing;
  // Within the band of the side and between the ends (a vertex moves only in its own turn, so
  // this is its position when its turn comes).
  auto in_band = [&](const glm::dvec3& p) {
    const double sv = cyl.s(p), off = cyl.rho(p) - cyl.r;
    return !(sv < spacing || sv > cyl.len - spacing || std::abs(off) > band || std::abs(off) <= 1e-9 * cyl.r);
  };
  // Every face around a vertex within the band of the side is a candidate (the reach covers it).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> corners;  // (old vertex in the band, candidate face)
  detail::VertexSlots& banded = detail::VertexSlots::scratch();  // each vertex judged once: 1 in the band
  banded.reset(posed.first_new());
  for (FaceId f : candidates)
    for (VertexId v : mesh.face(f)) {
      if (v.index >= posed.first_new()) continue;
      std::uint32_t b = banded.get(v.index);
      if (b == detail::VertexSlots::kNone) banded.set(v.index, b = in_band(posed(v)) ? 1 : 0);
      if (b == 1) corners.emplace_back(v.index, f.index);
    }
  std::sort(corners.begin(), corners.end());
  for (std::size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].first == corners[i].first) ++j;
    const VertexId x(corners[i].first);
    const glm::dvec3 p = posed(x);
    const double off = cyl.rho(p) - cyl.r;
    // The crossings its edges would get near it (entering from outside, leaving from inside).
    const glm::dvec3 m = cyl.perp(p);
    int near = 0;
    glm::dvec3 normal(0.0);
    for (std::size_t c = i; c < j; ++c) {
      const Triangle& t = mesh.face(FaceId(corners[c].second));
      normal += glm::cross(posed(t[1]) - posed(t[0]), posed(t[2]) - posed(t[0]));
    }
    // A vertex on the mesh's border stays where it is: primitives split at a material seam keep
    // a copy of each seam vertex each, and sliding one copy alone would open a crack along the
    // seam. It is on the border when an edge from it has a face on one side only.
    std::vector<VertexId>& ahead = border[0];
    std::vector<VertexId>& behind = border[1];
    ahead.clear();
    behind.clear();
    for (std::size_t c = i; c < j; ++c) {
      const Triangle& t = mesh.face(FaceId(corners[c].second));
      const int q = t[0] == x ? 0 : t[1] == x ? 1 : 2;
      ahead.push_back(t[(q + 1) % 3]);
      behind.push_back(t[(q + 2) % 3]);
    }
    std::sort(ahead.begin(), ahead.end());
    std::sort(behind.begin(), behind.end());
    if (ahead != behind) continue;
    // Its neighbours (the faces' corners other than x), each once: with the edges ahead and behind
    // alike, those ahead are all of them (x itself only in a face holding it twice).
    ring.assign(ahead.begin(), ahead.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    ring.erase(std::remove(ring.begin(), ring.end(), x), ring.end());
    for (VertexId y : ring) {
      const glm::dvec3 q = posed(y), k = cyl.perp(q) - m;
      const double a = glm::dot(k, k), b = glm::dot(m, k), cq = glm::dot(m, m) - cyl.r * cyl.r;
      const double disc = b * b - a * cq;
      if (!(a > 0.0) || disc < 0.0) continue;
      const double tt = off > 0.0 ? (-b - std::sqrt(disc)) / a : (-b + std::sqrt(disc)) / a;
      near += tt > 0.0 && tt < 1.0 && tt * glm::length(q - p) < close;
    }
    if (near < 2) continue;
    const double nl = glm::length(normal);
    if (!(nl > 0.0)) continue;
    normal /= nl;
    const glm::dvec3 radial = m / glm::length(m);
    glm::dvec3 dir = radial - glm::dot(radial, normal) * normal;
    const double dl = glm::length(dir);
    if (dl < 0.5) continue;  // the surface runs along the cylinder there: no slide reaches it
    dir /= dl;
    const glm::dvec3 k = dir - glm::dot(dir, cyl.d) * cyl.d;
    const double a = glm::dot(k, k), b = glm::dot(m, k), cq = glm::dot(m, m) - cyl.r * cyl.r;
    const double disc = b * b - a * cq;
    if (!(a > 0.0) || disc < 0.0) continue;
    const double l1 = (-b - std::sqrt(disc)) / a, l2 = (-b + std::sqrt(disc)) / a;
    const double step = std::abs(l1) < std::abs(l2) ? l1 : l2;
    if (!(std::abs(step) <= 2.0 * band)) continue;
    const glm::dvec3 target = p + step * dir;
    const double st = cyl.s(target);
    if (st < spacing || st > cyl.len - spacing) continue;
    const glm::vec3 bind = mesh.position(x);
    glm::dvec3 shift = target - p;
    if (posed.unpose())
      shift = glm::dvec3(posed.unpose()(mesh, x, glm::vec3(target))) -
              glm::dvec3(posed.unpose()(mesh, x, glm::vec3(p)));
    const glm::vec3 moved = glm::vec3(glm::dvec3(bind) + shift);
    if (!(std::isfinite(moved.x) && std::isfinite(moved.y) && std::isfinite(moved.z)) || moved == bind)
      continue;
    bool ok = true;
    for (std::size_t c = i; c < j && ok; ++c) {
      const Triangle& t = mesh.face(FaceId(corners[c].second));
      glm::dvec3 pp[3], pn[3], bp[3], bn[3];
      for (int q = 0; q < 3; ++q) {
        pp[q] = posed(t[q]);
        pn[q] = t[q] == x ? target : pp[q];
        bp[q] = glm::dvec3(mesh.position(t[q]));
        bn[q] = glm::dvec3(t[q] == x ? moved : mesh.position(t[q]));
      }
      for (int space = 0; space < 2 && ok; ++space) {
        const glm::dvec3* o = space == 0 ? pp : bp;
        const glm::dvec3* n = space == 0 ? pn : bn;
        const glm::dvec3 before = glm::cross(o[1] - o[0], o[2] - o[0]),
                         after = glm::cross(n[1] - n[0], n[2] - n[0]);
        const double longest =
            std::max({glm::dot(n[1] - n[0], n[1] - n[0]), glm::dot(n[2] - n[1], n[2] - n[1]),
                      glm::dot(n[0] - n[2], n[0] - n[2])});
        ok = glm::length(after) > 1e-9 * longest &&
             glm::dot(before, after) > 0.5 * glm::length(before) * glm::length(after);
      }
    }
    if (!ok) continue;
    editor.move_vertex(x, moved);
    posed.move(x, target);  // in index order: the corners are sorted
  }
}
}  // namespace deepcut::drill
