// SPDX-License-Identifier: MIT
#include "ops/cut/caps.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "deepcut/core/morph.h"
#include "ops/common/crossing_table.h"
#include "geometry/polygon_triangulation.h"

namespace deepcut::detail {
namespace {

bool flat(const std::vector<std::int8_t>& sign, const Triangle& t) {
  return sign[t[0].index] == 0 && sign[t[1].index] == 0 && sign[t[2].index] == 0;
}

// Closed rim loops as indices into `verts` (each rim vertex once).
struct RimLoops {
  std::vector<std::vector<std::uint32_t>> loops;
  std::vector<VertexId> verts;
};

// Follows the rim halfedges backwards (the cap runs along the piece's rim edges in the opposite
// direction) into closed loops; returns false if some rim chain is open. Each rim edge is used by
// one rim face, so every reversed halfedge b -> a is listed once: a flat list sorted by b (ties
// in halfedge order) with a used flag per entry.
bool trace_loops(const std::vector<std::pair<VertexId, VertexId>>& halfedges, RimLoops& out) {
  out.loops.clear();
  out.verts.clear();
  struct Step {
    std::uint32_t from, order, to;
  };
  std::vector<Step> steps;
  steps.reserve(halfedges.size());
  for (const auto& [a, b] : halfedges) steps.push_back({b.index, static_cast<std::uint32_t>(steps.size()), a.index});
  std::sort(steps.begin(), steps.end(),
            [](const Step& x, const Step& y) { return x.from != y.from ? x.from < y.from : x.order < y.order; });
  std::vector<char> used(steps.size(), 0);
  // The steps leaving v: [first, last) of `steps`.
  auto leaving = [&](std::uint32_t v) {
    const auto lo = std::lower_bound(steps.begin(), steps.end(), v, [](const Step& x, std::uint32_t k) { return x.from < k; });
    auto hi = lo;
    while (hi != steps.end() && hi->from == v) ++hi;
    return std::make_pair(static_cast<std::size_t>(lo - steps.begin()), static_cast<std::size_t>(hi - steps.begin()));
  };
  // Local index of each rim vertex, by first appearance in a kept loop.
  std::vector<std::uint32_t> ids;
  ids.reserve(2 * halfedges.size());
  for (const auto& [a, b] : halfedges) {
    ids.push_back(a.index);
    ids.push_back(b.index);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<std::uint32_t> local(ids.size(), kInvalidIndex);
  auto local_index = [&](std::uint32_t v) {
    std::uint32_t& l = local[static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), v) - ids.begin())];
    if (l == kInvalidIndex) {
      l = static_cast<std::uint32_t>(out.verts.size());
      out.verts.push_back(VertexId(v));
    }
    return l;
  };
  bool all_closed = true;
  std::vector<std::uint32_t> loop;
  for (std::size_t first = 0; first < steps.size(); ++first) {
    if (used[first]) continue;
    const std::uint32_t s = steps[first].from;
    loop.assign(1, s);
    std::size_t step = first;
    bool closed = false;
    while (true) {
      used[step] = 1;
      const std::uint32_t nxt = steps[step].to;
      if (nxt == s) {
        closed = true;
        break;
      }
      loop.push_back(nxt);
      const auto [lo, hi] = leaving(nxt);
      step = hi;
      for (std::size_t k = lo; k < hi && step == hi; ++k)
        if (!used[k]) step = k;
      if (step == hi) break;  // an open rim chain (open input): not capped
    }
    all_closed = all_closed && closed;
    if (closed && loop.size() >= 3) {
      std::vector<std::uint32_t> l;
      l.reserve(loop.size());
      for (std::uint32_t v : loop) l.push_back(local_index(v));
      out.loops.push_back(std::move(l));
    }
  }
  return all_closed;
}

// Faces of the piece lying in the plane (every corner on it) are where the cap goes: capping
// round them would put a second layer on top of them (a duplicate face, or cap triangles sharing
// their edges: non-manifold edges). When the rim closes without them they are removed and the
// cap takes their place; otherwise (open input) they stay and the rim is capped as it is, and
// they are returned: the cap must not repeat them.
std::vector<Triangle> choose_loops(MeshEditor& editor, const CapInput& in, std::vector<FaceId>& piece,
                                   RimLoops& rim) {
  const SurfaceMesh& mesh = editor.mesh();
  std::vector<FaceId> flat_faces;
  for (FaceId f : in.rim_faces)
    if (flat(*in.sign, mesh.face(f))) flat_faces.push_back(f);
  std::sort(flat_faces.begin(), flat_faces.end());
  std::vector<Triangle> kept_flat;
  if (flat_faces.empty() || !trace_loops(rim_halfedges(mesh, in, flat_faces), rim)) {
    for (FaceId f : flat_faces) kept_flat.push_back(mesh.face(f));
    flat_faces.clear();
    trace_loops(rim_halfedges(mesh, in), rim);
    // A rim loop that runs along a kept flat face (two of its corners on the loop) would be
    // capped over or beside that face, and cap triangles would share its edges (non-manifold
    // edges on open pieces). The surface there is partly in the plane already, and a cap of the
    // other loops could cover it as a hole, so the piece gets no cap rather than a doubled one.
    if (!kept_flat.empty()) {
      std::unordered_set<std::uint32_t> on_loop;
      for (const auto& loop : rim.loops)
        for (std::uint32_t i : loop) on_loop.insert(rim.verts[i].index);
      const bool runs_along = std::any_of(kept_flat.begin(), kept_flat.end(), [&](const Triangle& t) {
        return on_loop.count(t[0].index) + on_loop.count(t[1].index) + on_loop.count(t[2].index) >= 2;
      });
      if (runs_along) rim.loops.clear();
    }
  }
  if (!flat_faces.empty() && !rim.loops.empty()) {
    for (FaceId f : flat_faces) editor.remove_face(f);
    piece.erase(
        std::remove_if(piece.begin(), piece.end(),
                       [&](FaceId f) { return std::binary_search(flat_faces.begin(), flat_faces.end(), f); }),
        piece.end());
  }
  return kept_flat;
}

// Triangulates the loops in the plane's 2D frame and adds the cap faces with their attributes.
void add_cap_faces(MeshEditor& editor, const CapInput& in, const RimLoops& rim,
                   const std::vector<Triangle>& kept_flat, std::vector<FaceId>& piece) {
  auto repeats_flat = [&](Triangle t) {
    std::sort(t.begin(), t.end());
    return std::any_of(kept_flat.begin(), kept_flat.end(), [&](Triangle g) {
      std::sort(g.begin(), g.end());
      return g == t;
    });
  };
  const auto& loops = rim.loops;
  const auto& verts = rim.verts;
  // 2D frame in the plane.
  const glm::dvec3 n = in.normal;
  const glm::dvec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0))
                                                          : glm::cross(n, glm::dvec3(0, 1, 0)));
  const glm::dvec3 w = glm::cross(n, u);
  std::vector<glm::dvec2> pts(verts.size());
  for (std::size_t i = 0; i < verts.size(); ++i) {
    const glm::dvec3 p = glm::dvec3((*in.posed)(verts[i])) - in.point;
    pts[i] = {glm::dot(p, u), glm::dot(p, w)};
  }
  // The largest loop is an outer one; its orientation is the cap's.
  std::size_t largest = 0;
  for (std::size_t i = 1; i < loops.size(); ++i)
    if (std::abs(geometry::signed_area2(pts, loops[i])) > std::abs(geometry::signed_area2(pts, loops[largest]))) largest = i;
  const int outer_sign = geometry::signed_area2(pts, loops[largest]) >= 0 ? 1 : -1;
  const auto tris = geometry::triangulate_loops(pts, loops, outer_sign);

  SurfaceMesh& mesh = editor.mesh();
  auto& ca = mesh.corner_attrs();
  auto* cap_flag = mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface);
  if (!cap_flag) cap_flag = &mesh.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  auto* uv = ca.find<glm::vec2>(attr::kUv0);
  auto* normals = ca.find<glm::vec3>(attr::kNormal);
  auto* tangents = ca.find<glm::vec4>(attr::kTangent);
  auto* colors = ca.find<glm::vec4>(attr::kColor0);
  const auto morph_deltas = corner_morph_deltas(mesh);
  double extent = 0.0;
  for (const auto& p : pts) extent = std::max({extent, std::abs(p.x), std::abs(p.y)});
  if (extent <= 0.0) extent = 1.0;
  const auto& bind = mesh.positions();
  piece.reserve(piece.size() + tris.size());
  for (const auto& tri : tris) {
    const Triangle t = {verts[tri[0]], verts[tri[1]], verts[tri[2]]};
    if (repeats_flat(t)) continue;  // that surface is there already
    const FaceId f = editor.add_face(t);
    piece.push_back(f);
    (*cap_flag)[f.index] = 1;
    glm::vec3 fn = glm::cross(bind[t[1].index] - bind[t[0].index], bind[t[2].index] - bind[t[0].index]);
    const float len = glm::length(fn);
    fn = len > 0.0f ? fn / len : glm::vec3(float(outer_sign) * glm::vec3(n));
    for (int k = 0; k < 3; ++k) {
      const auto c = SurfaceMesh::corner(f, k);
      const glm::dvec2 p = pts[tri[k]];
      if (uv) (*uv)[c] = glm::vec2(0.5 + 0.5 * p.x / extent, 0.5 + 0.5 * p.y / extent);
      if (normals) (*normals)[c] = fn;
      if (tangents) (*tangents)[c] = glm::vec4(glm::vec3(u), 1.0f);
      if (colors) (*colors)[c] = glm::vec4(1.0f);
      for (auto* d : morph_deltas) (*d)[c] = glm::vec3(0.0f);
    }
  }
}

}  // namespace

std::vector<std::pair<VertexId, VertexId>> rim_halfedges(const SurfaceMesh& mesh, const CapInput& in,
                                                         const std::vector<FaceId>& skip) {
  // An edge with both ends on the plane belongs only to faces with two corners on it, so
  // counting within the rim faces is exact. The on-plane halfedges in face order, and their
  // edge keys with their places sorted: a key listed once is a rim edge.
  const auto& sign = *in.sign;
  std::vector<std::pair<VertexId, VertexId>> halfedges;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys;
  halfedges.reserve(2 * in.rim_faces.size());
  keys.reserve(2 * in.rim_faces.size());
  for (FaceId f : in.rim_faces) {
    if (!skip.empty() && std::binary_search(skip.begin(), skip.end(), f)) continue;
    const auto& t = mesh.face(f);
    for (int k = 0; k < 3; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      if (sign[a.index] != 0 || sign[b.index] != 0) continue;
      keys.emplace_back(edge_key(a, b), static_cast<std::uint32_t>(halfedges.size()));
      halfedges.emplace_back(a, b);
    }
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint8_t> once(keys.size(), 0);
  for (std::size_t i = 0; i < keys.size(); ++i)
    once[keys[i].second] = (i == 0 || keys[i - 1].first != keys[i].first) &&
                           (i + 1 == keys.size() || keys[i + 1].first != keys[i].first);
  std::size_t n = 0;
  for (std::size_t i = 0; i < halfedges.size(); ++i)
    if (once[i]) halfedges[n++] = halfedges[i];
  halfedges.resize(n);
  return halfedges;
}

void cap_piece(MeshEditor& editor, const CapInput& in, std::vector<FaceId>& piece) {
  RimLoops rim;
  const std::vector<Triangle> kept_flat = choose_loops(editor, in, piece, rim);
  if (rim.loops.empty()) return;
  add_cap_faces(editor, in, rim, kept_flat, piece);
}

}  // namespace deepcut::detail
