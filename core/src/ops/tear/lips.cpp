// SPDX-License-Identifier: MIT
// Lips: the torn edges made into two lips that separate. The stages: lone torn edges split ->
// chains (the torn edges as a graph over their vertices) -> wedges (the faces around each chain
// vertex between torn edges) -> taper (arc length to each slit's nearer end) -> lip normals ->
// split (one vertex copy per wedge) -> open (lips pushed apart, capped and halved so no face
// flips or loses its area).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <queue>

#include "geometry/predicates.h"
#include "ops/tear/stages.h"

namespace deepcut::detail::tear {
namespace {

// The torn edges as a graph: neighbours of each chain vertex (sorted), the chain vertices sorted.
struct Chains {
  explicit Chains(std::pmr::memory_resource* arena) : graph(arena) {}
  Map<std::uint32_t, std::vector<std::uint32_t>> graph;
  std::vector<std::uint32_t> vertices;
};

// Faces around each chain vertex, grouped into wedges: faces connected across edges (v, x) that
// are not torn. Wedges in order of their first face in the vertex's star.
struct Wedges {
  explicit Wedges(std::pmr::memory_resource* arena) : of(arena), on_boundary(arena) {}
  Map<std::uint32_t, std::vector<std::vector<FaceId>>> of;
  Set<std::uint32_t> on_boundary;  // chain vertices on a boundary before this tear
};

// Slits (connected parts of the chains): each chain vertex's slit, each slit's length and whether
// it has an end, and the arc length from each vertex to its slit's nearest end.
struct Taper {
  explicit Taper(std::pmr::memory_resource* arena) : to_end(arena), comp(arena) {}
  Map<std::uint32_t, double> to_end;
  Map<std::uint32_t, std::uint32_t> comp;
  std::vector<double> comp_length;
  std::vector<bool> comp_has_end;
};

// The normal of the facet(s) that tore each chain vertex's edges (summed), and those facets.
struct LipNormals {
  explicit LipNormals(std::pmr::memory_resource* arena) : normal(arena), facets(arena) {}
  Map<std::uint32_t, glm::dvec3> normal;
  Map<std::uint32_t, std::vector<std::size_t>> facets;
};

struct Lip {
  VertexId v;        // vertex or copy
  std::uint32_t of;  // chain vertex it came from
  std::vector<FaceId> faces;
  glm::dvec3 move{0.0};  // world displacement
};

// The lips after the split: wedge 0 of a chain vertex keeps the vertex, every other wedge a copy.
struct Lips {
  explicit Lips(std::pmr::memory_resource* arena) : split_from(arena) {}
  std::vector<Lip> lips;
  std::vector<VertexId> tear_vertices;  // sorted
  Set<std::uint32_t> split_from;        // copies made by the split
};

Chains build_chains(const TearContext& ctx, const Slits& slits) {
  Chains c(ctx.arena);
  for (const auto& [key, facet] : slits.torn) {
    const auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xffffffffu);
    c.graph[a].push_back(b);
    c.graph[b].push_back(a);
  }
  for (const auto& [v, nb] : c.graph) c.vertices.push_back(v);
  std::sort(c.vertices.begin(), c.vertices.end());
  for (auto& [v, nb] : c.graph) std::sort(nb.begin(), nb.end());
  return c;
}

// The wedges of chain vertex `v` from its star `fs`; notes `v` in `on_boundary` when one of its
// untorn edges has a single face.
std::vector<std::vector<FaceId>> wedges_at(const TearContext& ctx, const Slits& slits, std::uint32_t v,
                                           const std::vector<FaceId>& fs, Set<std::uint32_t>& on_boundary) {
  std::vector<std::uint32_t> parent(fs.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // (neighbour, face) pairs, grouped by neighbour with the faces in star order.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> around;
  around.reserve(2 * fs.size());
  for (std::uint32_t i = 0; i < fs.size(); ++i) {
    const Triangle& t = ctx.mesh.face(fs[i]);
    for (int k = 0; k < 3; ++k)
      if (t[k].index == v) {
        around.emplace_back(t[(k + 1) % 3].index, i);
        around.emplace_back(t[(k + 2) % 3].index, i);
      }
  }
  std::stable_sort(around.begin(), around.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const std::size_t n_around = around.size();
  for (std::size_t lo = 0, hi = 0; lo < n_around; lo = hi) {
    const std::uint32_t x = around[lo].first;
    hi = lo + 1;
    while (hi < n_around && around[hi].first == x) ++hi;
    const bool torn = slits.torn.count(edge_key(VertexId(v), VertexId(x))) != 0;
    if (hi - lo == 1 && !torn) on_boundary.insert(v);
    if (torn) continue;
    for (std::size_t i = lo + 1; i < hi; ++i) {
      const auto a = root(around[lo].second), b = root(around[i].second);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // A set's root is its smallest member, so groups in order of first member are groups in order
  // of root.
  std::vector<std::vector<FaceId>> list;
  std::vector<std::uint32_t> group_of(fs.size(), kInvalidIndex);
  for (std::uint32_t i = 0; i < fs.size(); ++i) {
    const std::uint32_t r = root(i);
    if (group_of[r] == kInvalidIndex) {
      group_of[r] = static_cast<std::uint32_t>(list.size());
      list.emplace_back();
    }
    list[group_of[r]].push_back(fs[i]);
  }
  return list;
}

Wedges find_wedges(const TearContext& ctx, Slits& slits, const Chains& chains) {
  // Stars of the chain vertices (every face around a chain vertex is in the region).
  std::sort(slits.region.begin(), slits.region.end());
  slits.region.erase(std::unique(slits.region.begin(), slits.region.end()), slits.region.end());
  Map<std::uint32_t, std::vector<FaceId>> star(ctx.arena);
  for (FaceId f : slits.region) {
    if (ctx.mesh.is_deleted(f)) continue;
    for (auto v : ctx.mesh.face(f))
      if (chains.graph.count(v.index)) star[v.index].push_back(f);
  }
  Wedges w(ctx.arena);
  for (std::uint32_t v : chains.vertices) w.of[v] = wedges_at(ctx, slits, v, star[v], w.on_boundary);
  return w;
}

// Taper along each slit: arc length to the nearest end (torn degree 1, or an old boundary).
Taper measure_slits(const TearContext& ctx, const Chains& chains, const Set<std::uint32_t>& on_boundary) {
  Taper tp(ctx.arena);
  const auto& graph = chains.graph;
  auto edge_len = [&](std::uint32_t a, std::uint32_t b) {
    return static_cast<double>(glm::length(ctx.pose.posed(a) - ctx.pose.posed(b)));
  };
  for (std::uint32_t v : chains.vertices) {
    if (tp.comp.count(v)) continue;
    const auto c = static_cast<std::uint32_t>(tp.comp_length.size());
    tp.comp_length.push_back(0.0);
    tp.comp_has_end.push_back(false);
    std::vector<std::uint32_t> stack = {v}, members;
    tp.comp[v] = c;
    while (!stack.empty()) {
      const auto x = stack.back();
      stack.pop_back();
      members.push_back(x);
      for (auto y : graph.at(x)) {
        if (x < y) tp.comp_length[c] += edge_len(x, y);
        if (!tp.comp.count(y)) {
          tp.comp[y] = c;
          stack.push_back(y);
        }
      }
    }
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (auto x : members) {
      if (graph.at(x).size() == 1 || on_boundary.count(x)) {
        tp.to_end[x] = 0.0;
        queue.emplace(0.0, x);
        tp.comp_has_end[c] = true;
      }
    }
    while (!queue.empty()) {
      const auto [d, x] = queue.top();
      queue.pop();
      if (d > tp.to_end[x]) continue;
      for (auto y : graph.at(x)) {
        const double nd = d + edge_len(x, y);
        auto it = tp.to_end.find(y);
        if (it == tp.to_end.end() || nd < it->second) {
          tp.to_end[y] = nd;
          queue.emplace(nd, y);
        }
      }
    }
  }
  return tp;
}

// Lip normal at each chain vertex: the normal of the facet(s) that tore its edges.
LipNormals lip_normals(const TearContext& ctx, const Slits& slits, const std::vector<SweepFacet>& facets) {
  LipNormals ln(ctx.arena);
  for (const auto& [key, facet] : slits.torn) {
    for (const auto v : {static_cast<std::uint32_t>(key >> 32), static_cast<std::uint32_t>(key & 0xffffffffu)}) {
      auto& list = ln.facets[v];
      if (std::find(list.begin(), list.end(), facet) == list.end()) {
        list.push_back(facet);
        ln.normal[v] += facets[facet].normal;
      }
    }
  }
  return ln;
}

// Split: wedge 0 keeps the vertex, every other wedge gets a copy, and its faces are made again on
// the copy.
Lips split_lips(TearContext& ctx, const Chains& chains, Wedges& wedges) {
  Lips out(ctx.arena);
  Map<std::uint32_t, std::vector<std::pair<std::uint32_t, VertexId>>> replace(ctx.arena);  // face -> (old, new)
  for (std::uint32_t v : chains.vertices) {
    auto& ws = wedges.of[v];
    out.tear_vertices.push_back(VertexId(v));
    if (ws.size() < 2) continue;
    for (std::size_t w = 0; w < ws.size(); ++w) {
      VertexId id(v);
      if (w > 0) {
        id = ctx.editor.split_vertex(VertexId(v));
        ctx.pose.add_copy(id, VertexId(v));
        out.tear_vertices.push_back(id);
        out.split_from.insert(id.index);
        for (FaceId f : ws[w]) replace[f.index].emplace_back(v, id);
      }
      out.lips.push_back({id, v, ws[w], glm::dvec3(0.0)});
    }
  }
  Map<std::uint32_t, FaceId> renamed(ctx.arena);
  std::vector<std::uint32_t> replaced_faces;
  for (const auto& [f, list] : replace) replaced_faces.push_back(f);
  std::sort(replaced_faces.begin(), replaced_faces.end());
  const glm::vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (std::uint32_t fi : replaced_faces) {
    Triangle t = ctx.mesh.face(FaceId(fi));
    for (const auto& [old, copy] : replace[fi])
      for (auto& v : t)
        if (v.index == old) v = copy;
    ctx.editor.remove_face(FaceId(fi));
    renamed.emplace(fi, ctx.editor.add_face_from(t, FaceId(fi), {e[0], e[1], e[2]}));
  }
  for (Lip& lip : out.lips)
    for (FaceId& f : lip.faces) {
      auto it = renamed.find(f.index);
      if (it != renamed.end()) f = it->second;
    }
  std::sort(out.tear_vertices.begin(), out.tear_vertices.end());
  return out;
}

// The world move of one lip: half the width, tapered, away from the plane on its own side, no
// further than the longest edge of its faces. None when the lip has no normal or taper, or its
// side is undecided.
std::optional<glm::dvec3> lip_move(const TearContext& ctx, const Lip& lip, const Chains& chains, const Lips& lips,
                    const LipNormals& ln, const std::vector<SweepFacet>& facets, double taper, float width) {
  glm::dvec3 n = ln.normal.at(lip.of);
  if (glm::length(n) == 0.0 || taper <= 0.0) return std::nullopt;
  n = glm::normalize(n);
  // Which side the wedge lies on: its vertices off the tear, measured against the plane(s) of the
  // facet(s) that tore this vertex (the centroids would mislead at a folded quad's crease, where
  // the other facet's lip vertices stand off the mean plane).
  double side = 0.0, fallback = 0.0;
  const glm::dvec3 pv(ctx.pose.posed(lip.of));
  const auto& planes = ln.facets.at(lip.of);
  for (FaceId f : lip.faces) {
    const Triangle& t = ctx.mesh.face(f);
    glm::dvec3 centre(0.0);
    for (auto x : t) {
      const glm::dvec3 px(ctx.pose.posed(x.index));
      centre += px / 3.0;
      if (chains.graph.count(x.index) || lips.split_from.count(x.index)) continue;
      side += nearest_side(facets, planes, px);
    }
    fallback += glm::dot(centre - pv, n);
  }
  if (side == 0.0) side = fallback;
  if (side == 0.0) return std::nullopt;
  // No lip moves further than the longest edge of its faces: a longer move flips them anyway, and
  // halving from a huge width (1e9) would give up before reaching a size that fits.
  double reach = 0.0;
  for (FaceId f : lip.faces) {
    const Triangle& t = ctx.mesh.face(f);
    for (int k = 0; k < 3; ++k)
      reach = std::max(reach, glm::length(glm::dvec3(ctx.pose.posed(t[k].index)) -
                                          glm::dvec3(ctx.pose.posed(t[(k + 1) % 3].index))));
  }
  const double half = std::min(0.5 * double(width) * taper, reach);
  return (side > 0.0 ? 1.0 : -1.0) * half * n;
}

// Plans every lip's move; returns the lip of each moving vertex.
Map<std::uint32_t, std::size_t> plan_moves(const TearContext& ctx, Lips& lips, const Chains& chains, Taper& tp,
                                           const LipNormals& ln, const std::vector<SweepFacet>& facets, float width) {
  Map<std::uint32_t, std::size_t> lip_of(ctx.arena);  // vertex -> lip
  for (std::size_t i = 0; i < lips.lips.size(); ++i) {
    Lip& lip = lips.lips[i];
    const std::uint32_t c = tp.comp[lip.of];
    const double length = tp.comp_length[c];
    double taper = 1.0;
    if (tp.comp_has_end[c] && length > 0.0) {
      auto it = tp.to_end.find(lip.of);
      const double d = it == tp.to_end.end() ? 0.5 * length : std::min(it->second, 0.5 * length);
      taper = std::sin(geometry::kPi * d / length);
    }
    const std::optional<glm::dvec3> move = lip_move(ctx, lip, chains, lips, ln, facets, taper, width);
    if (!move) continue;
    lip.move = *move;
    lip_of.emplace(lip.v.index, i);
  }
  return lip_of;
}

}  // namespace

namespace {

// Halves moves that would flip a face (or nearly collapse it), until none does (at most 12
// rounds, the last one cancelling). Returns the faces of the moving lips, sorted.
std::vector<FaceId> halve_flipping_moves(const TearContext& ctx, Lips& lips, const Map<std::uint32_t, std::size_t>& lip_of) {
  std::vector<FaceId> check;
  for (const Lip& lip : lips.lips)
    if (glm::length(lip.move) > 0.0) check.insert(check.end(), lip.faces.begin(), lip.faces.end());
  std::sort(check.begin(), check.end());
  check.erase(std::unique(check.begin(), check.end()), check.end());
  // Each face's corners and lips are looked up once. A face is evaluated again only when one of
  // its lips changed since its last evaluation (at or after it, in face order): otherwise it would
  // pass again, so the rounds give what evaluating every face every round gives.
  struct Check {
    glm::dvec3 p[3];
    glm::dvec3 n0;
    double l0;
    std::uint32_t lip[3];
    std::uint64_t evaluated = 0;  // clock of the last evaluation (0: never)
  };
  std::vector<Check> checks;
  checks.reserve(check.size());
  for (FaceId f : check) {
    const Triangle& t = ctx.mesh.face(f);
    Check c;
    for (int k = 0; k < 3; ++k) {
      c.p[k] = glm::dvec3(ctx.pose.posed(t[k].index));
      auto it = lip_of.find(t[k].index);
      c.lip[k] = it == lip_of.end() ? kInvalidIndex : static_cast<std::uint32_t>(it->second);
    }
    c.n0 = glm::cross(c.p[1] - c.p[0], c.p[2] - c.p[0]);
    c.l0 = glm::length(c.n0);
    if (c.l0 == 0.0) continue;  // never flips, never halves
    checks.push_back(c);
  }
  std::vector<std::uint64_t> changed(lips.lips.size(), 0);  // clock of each lip's last halving
  std::uint64_t clock = 0;
  for (int round = 0; round < 12; ++round) {
    bool flipped = false;
    for (Check& c : checks) {
      if (c.evaluated != 0) {
        bool dirty = false;
        for (std::uint32_t l : c.lip) dirty |= l != kInvalidIndex && changed[l] >= c.evaluated;
        if (!dirty) continue;
      }
      c.evaluated = ++clock;
      glm::dvec3 m[3];
      for (int k = 0; k < 3; ++k) m[k] = c.lip[k] == kInvalidIndex ? c.p[k] : c.p[k] + lips.lips[c.lip[k]].move;
      const glm::dvec3 n1 = glm::cross(m[1] - m[0], m[2] - m[0]);
      if (glm::dot(c.n0, n1) > 0.25 * c.l0 * glm::length(n1) && glm::length(n1) > 0.2 * c.l0) continue;
      flipped = true;
      for (std::uint32_t l : c.lip)
        if (l != kInvalidIndex) {
          lips.lips[l].move *= round == 11 ? 0.0 : 0.5;
          changed[l] = clock;
        }
    }
    if (!flipped) break;
  }
  return check;
}

// Bind positions after the opening, as stored (float). Two lip vertices a few float steps apart
// (the crossings of a needle, a sliver's corners) moved together can round onto one point, which
// the flip check (posed, in double) cannot see: a face that would lose its area keeps its lips
// where they were, until no face does. Sets `moving` and `target` per lip.
void keep_face_areas(const TearContext& ctx, const Lips& lips, const Map<std::uint32_t, std::size_t>& lip_of,
                     const std::vector<FaceId>& check, std::vector<glm::vec3>& target, std::vector<bool>& moving) {
  target.assign(lips.lips.size(), glm::vec3());
  moving.assign(lips.lips.size(), false);
  for (std::size_t i = 0; i < lips.lips.size(); ++i) {
    if (glm::length(lips.lips[i].move) == 0.0) continue;
    const VertexId v = lips.lips[i].v;
    const glm::mat3 m = ctx.pose.linear(v);
    if (std::abs(glm::determinant(m)) < 1e-12f) continue;
    // Posed, the lip moves by exactly its move: its moved posed point unposed.
    const glm::vec3 guess = ctx.mesh.position(v) + glm::inverse(m) * glm::vec3(lips.lips[i].move);
    const glm::vec3 to = glm::vec3(glm::dvec3(ctx.pose.posed(v.index)) + lips.lips[i].move);
    target[i] = ctx.pose.placement().bind_position(ctx.mesh, v, to, guess);
    moving[i] = true;
  }
  auto has_area = [](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::dvec3 x(a), y(b), z(c);
    return glm::length(glm::cross(y - x, z - x)) > 0.0;
  };
  for (bool again = true; again;) {
    again = false;
    for (FaceId f : check) {
      const Triangle& t = ctx.mesh.face(f);
      glm::vec3 p[3];
      bool moved = false;
      std::uint32_t lip[3];
      for (int k = 0; k < 3; ++k) {
        auto it = lip_of.find(t[k].index);
        lip[k] = it == lip_of.end() ? kInvalidIndex : static_cast<std::uint32_t>(it->second);
        moved |= lip[k] != kInvalidIndex && moving[lip[k]];
        p[k] = lip[k] != kInvalidIndex && moving[lip[k]] ? target[lip[k]] : ctx.mesh.position(t[k]);
      }
      if (!moved || has_area(p[0], p[1], p[2]) ||
          !has_area(ctx.mesh.position(t[0]), ctx.mesh.position(t[1]), ctx.mesh.position(t[2])))
        continue;
      for (std::uint32_t l : lip)
        if (l != kInvalidIndex) moving[l] = false;
      again = true;
    }
  }
}

// Opening: each lip moves half the width, tapered, away from the plane on its own side; moves
// are capped, halved and dropped so no face flips or loses its area. Returns the opening
// achieved: the widest gap between two copies of one slit vertex.
float open_lips(TearContext& ctx, Lips& lips, const Chains& chains, Taper& tp, const LipNormals& ln,
                const std::vector<SweepFacet>& facets, float width) {
  const Map<std::uint32_t, std::size_t> lip_of = plan_moves(ctx, lips, chains, tp, ln, facets, width);
  const std::vector<FaceId> check = halve_flipping_moves(ctx, lips, lip_of);
  std::vector<glm::vec3> target;
  std::vector<bool> moving;
  keep_face_areas(ctx, lips, lip_of, check, target, moving);
  for (std::size_t i = 0; i < lips.lips.size(); ++i)
    if (!moving[i]) lips.lips[i].move = glm::dvec3(0.0);
  Map<std::uint32_t, std::vector<glm::dvec3>> moves_of(ctx.arena);
  for (const Lip& lip : lips.lips) moves_of[lip.of].push_back(lip.move);
  double opening = 0.0;
  for (const auto& [of, moves] : moves_of)
    for (std::size_t i = 0; i < moves.size(); ++i)
      for (std::size_t j = i + 1; j < moves.size(); ++j) opening = std::max(opening, glm::length(moves[i] - moves[j]));
  for (std::size_t i = 0; i < lips.lips.size(); ++i)
    if (moving[i]) ctx.editor.move_vertex(lips.lips[i].v, target[i]);
  return static_cast<float>(opening);
}

}  // namespace

void split_lone_edges(TearContext& ctx, Slits& slits) {
  Map<std::uint32_t, int> degree(ctx.arena);
  for (const auto& [key, facet] : slits.torn) {
    ++degree[key_lo(key).index];
    ++degree[key_hi(key).index];
  }
  std::vector<std::uint64_t> lone;
  for (const auto& [key, facet] : slits.torn)
    if (degree[key_lo(key).index] == 1 && degree[key_hi(key).index] == 1) lone.push_back(key);
  if (lone.empty()) return;
  std::sort(lone.begin(), lone.end());
  Map<std::uint64_t, std::vector<FaceId>> faces_of(ctx.arena);
  for (std::uint64_t key : lone) faces_of[key];
  std::sort(slits.region.begin(), slits.region.end());
  slits.region.erase(std::unique(slits.region.begin(), slits.region.end()), slits.region.end());
  for (FaceId f : slits.region) {
    if (ctx.mesh.is_deleted(f)) continue;
    const Triangle& t = ctx.mesh.face(f);
    for (int k = 0; k < 3; ++k) {
      auto it = faces_of.find(edge_key(t[k], t[(k + 1) % 3]));
      if (it != faces_of.end()) it->second.push_back(f);
    }
  }
  for (std::uint64_t key : lone) {
    const VertexId a = key_lo(key), b = key_hi(key);
    const std::size_t facet = slits.torn.at(key);
    const VertexId m = ctx.editor.add_vertex_on_edge(a, b, 0.5f);
    const VertexId src[2] = {a, b};
    const double w[2] = {0.5, 0.5};
    const glm::dvec3 at = 0.5 * (glm::dvec3(ctx.pose.posed(a.index)) + glm::dvec3(ctx.pose.posed(b.index)));
    ctx.pose.add(ctx.editor, m, at, src, w, 2);
    for (FaceId f : faces_of[key]) {
      const Triangle t = ctx.mesh.face(f);
      int k = 0;
      while (edge_key(t[k], t[(k + 1) % 3]) != key) ++k;
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      glm::vec3 ek(0.0f), ek1(0.0f), ek2(0.0f), mid(0.0f);
      ek[k] = 1.0f;
      ek1[k1] = 1.0f;
      ek2[k2] = 1.0f;
      mid[k] = 0.5f;
      mid[k1] = 0.5f;
      ctx.editor.remove_face(f);
      slits.region.push_back(ctx.editor.add_face_from({t[k], m, t[k2]}, f, {ek, mid, ek2}));
      slits.region.push_back(ctx.editor.add_face_from({m, t[k1], t[k2]}, f, {mid, ek1, ek2}));
    }
    slits.torn.erase(key);
    slits.add_torn(a, m, facet);
    slits.add_torn(m, b, facet);
  }
}

Separation separate_and_open(TearContext& ctx, const std::vector<SweepFacet>& facets, float width, Slits& slits) {
  Separation out;
  const Chains chains = build_chains(ctx, slits);
  Wedges wedges = find_wedges(ctx, slits, chains);
  Taper taper = measure_slits(ctx, chains, wedges.on_boundary);
  out.slits = taper.comp_length.size();
  for (bool has_end : taper.comp_has_end) out.closed_slits += has_end ? 0 : 1;
  const LipNormals normals = lip_normals(ctx, slits, facets);
  Lips lips = split_lips(ctx, chains, wedges);
  out.tear_vertices = lips.tear_vertices;
  if (width > 0.0f) out.opening = open_lips(ctx, lips, chains, taper, normals, facets, width);
  return out;
}

}  // namespace deepcut::detail::tear
