// SPDX-License-Identifier: MIT
#include "ops/common/pinches.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "ops/common/vertex_slots.h"
#include "sorted_ids.h"
#include "union_find.h"

namespace deepcut::detail {

std::vector<VertexId> edited_vertices(const EditLog& log) {
  std::vector<VertexId> out;
  for (const Edit& e : log.edits) {
    if (const auto* a = std::get_if<FaceAdded>(&e)) {
      out.insert(out.end(), a->vertices.begin(), a->vertices.end());
    } else if (const auto* r = std::get_if<FaceRemoved>(&e)) {
      out.insert(out.end(), r->vertices.begin(), r->vertices.end());
    } else if (const auto* s = std::get_if<VertexSplit>(&e)) {
      out.push_back(s->original);
      out.push_back(s->copy);
    }
  }
  sort_unique_ids(out);
  return out;
}

std::vector<FaceId> faces_using(const SurfaceMesh& mesh, const std::vector<VertexId>& vertices) {
  std::vector<FaceId> out;
  if (vertices.empty()) return out;
  std::vector<bool> wanted(mesh.vertex_count(), false);
  for (const VertexId v : vertices)
    if (v.index < wanted.size()) wanted[v.index] = true;
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    if (wanted[t[0].index] || wanted[t[1].index] || wanted[t[2].index]) out.push_back(f);
  });
  return out;
}

std::vector<FaceId> faces_around(const SurfaceMesh& mesh, const EditLog& log, const std::vector<VertexId>& vertices,
                                 std::uint32_t first_new_vertex, const TriangleGrid* index,
                                 const std::vector<glm::vec3>& input_posed) {
  if (!index) return faces_using(mesh, vertices);
  VertexSlots& wanted = VertexSlots::scratch();
  wanted.reset(mesh.vertex_count());
  for (const VertexId v : vertices)
    if (v.index < mesh.vertex_count()) wanted.set(v.index, 0);
  // Only live faces using one of `vertices` are kept (the grid's cells hold many more).
  std::vector<FaceId> out;
  auto keep = [&](FaceId f) {
    if (f.index >= mesh.face_slots() || mesh.is_deleted(f)) return;
    const Triangle& t = mesh.face(f);
    if (wanted.has(t[0].index) || wanted.has(t[1].index) || wanted.has(t[2].index)) out.push_back(f);
  };
  for (const Edit& e : log.edits)
    if (const auto* a = std::get_if<FaceAdded>(&e)) keep(a->f);
  // Every face using an old vertex v had v's position inside its box when the grid was built:
  // the faces filed in the cells of those positions (each cell visited once).
  std::vector<glm::vec3> points;
  points.reserve(vertices.size());
  for (const VertexId v : vertices)
    if (v.index < first_new_vertex && v.index < input_posed.size()) points.push_back(input_posed[v.index]);
  for (const FaceId f : index->query_points(points)) keep(f);
  sort_unique_ids(out);
  return out;
}

namespace {

// Fans around one vertex wider than this are found by sorting their faces' other corners; up to
// it, by comparing every pair of faces (fewer steps for the usual handful).
constexpr std::size_t kPairwiseFans = 16;

// Each face's two corners other than `v` (o0, o1), for up to kPairwiseFans faces each using `v`
// at one corner only; false for any other list.
bool other_corners(const SurfaceMesh& mesh, VertexId v, const FaceId* fs, std::size_t size, std::uint32_t* o0,
                   std::uint32_t* o1) {
  if (size > kPairwiseFans) return false;
  for (std::size_t i = 0; i < size; ++i) {
    const Triangle& t = mesh.face(fs[i]);
    if ((t[0] == v) + (t[1] == v) + (t[2] == v) != 1) return false;
    const int q = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    o0[i] = t[(q + 1) % 3].index;
    o1[i] = t[(q + 2) % 3].index;
  }
  return true;
}

// The fans of up to kPairwiseFans faces given by their other corners (other_corners), found by
// comparing pairs: each fan is grown over a bit set from its lowest face, each face taken once
// and compared with the faces not reached yet. With `parent`, each face's entry is set to its
// fan's lowest index (a forest of depth one, as find_fans makes); without, it stops at the
// second fan. True when there are two fans or more.
bool pairwise_fans(const std::uint32_t* o0, const std::uint32_t* o1, std::size_t size,
                   std::uint32_t* parent) {
  static_assert(kPairwiseFans <= 32, "one bit per face");
  auto shares_other = [&](int i, int j) {
    return o0[j] == o0[i] || o0[j] == o1[i] || o1[j] == o0[i] || o1[j] == o1[i];
  };
  const std::uint32_t all = size == 32 ? ~0u : (1u << size) - 1u;
  std::uint32_t reached = 0;
  int fans = 0;
  while (reached != all) {
    const int root = __builtin_ctz(all & ~reached);
    if (++fans > 1 && !parent) return true;
    const std::uint32_t before = reached;
    reached |= 1u << root;
    std::uint32_t open = 1u << root;  // reached, neighbours not looked for yet
    while (open != 0 && reached != all) {
      const int i = __builtin_ctz(open);
      open &= open - 1;
      for (std::uint32_t rest = all & ~reached; rest != 0; rest &= rest - 1) {
        const int j = __builtin_ctz(rest);
        if (shares_other(i, j)) {
          reached |= 1u << j;
          open |= 1u << j;
        }
      }
    }
    if (parent)
      for (std::uint32_t fan = reached & ~before; fan != 0; fan &= fan - 1) parent[__builtin_ctz(fan)] = root;
  }
  return fans > 1;
}

// The fans of the faces `fs` around `v` (faces joined through an edge (v, u), i.e. sharing a
// second vertex u) as a forest in `parent` whose roots are each fan's lowest index: pairwise_fans
// for the usual handful, else a union-find over the faces sorted by their other corners (the
// higher root always links under the lower, whatever order the unions come in). `forest` false:
// only whether there are two fans, `parent` left unspecified. True when there are two fans or more.
bool find_fans(const SurfaceMesh& mesh, VertexId v, const FaceId* fs, std::size_t size, bool forest,
               std::vector<std::uint32_t>& parent,
               std::vector<std::pair<std::uint32_t, std::uint32_t>>& by_other) {
  std::uint32_t o0[kPairwiseFans], o1[kPairwiseFans];
  if (other_corners(mesh, v, fs, size, o0, o1)) {
    if (!forest) return pairwise_fans(o0, o1, size, nullptr);
    parent.resize(size);
    return pairwise_fans(o0, o1, size, parent.data());
  }
  parent.resize(size);
  std::iota(parent.begin(), parent.end(), 0u);
  auto unite = [&](std::uint32_t i, std::uint32_t j) {
    const auto a = find_root(parent, i), b = find_root(parent, j);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  by_other.clear();
  for (std::uint32_t i = 0; i < size; ++i)
    for (const VertexId u : mesh.face(fs[i]))
      if (u != v) by_other.emplace_back(u.index, i);
  std::sort(by_other.begin(), by_other.end());
  for (std::size_t i = 1; i < by_other.size(); ++i)
    if (by_other[i].first == by_other[i - 1].first) unite(by_other[i].second, by_other[i - 1].second);
  bool several = false;
  for (std::uint32_t i = 0; i < size; ++i) several |= find_root(parent, i) != 0;
  return several;
}

// The live faces of `incident` (a face may be listed twice) grouped by the candidates among their
// corners (`slot` of a corner: its candidate, `count` for none), each group in id order: candidate
// s's faces are [first[s], first[s + 1]) of the list returned.
template <class Slot>
std::vector<FaceId> faces_by_candidate(const SurfaceMesh& mesh, const std::vector<FaceId>& incident,
                                       std::size_t count, const Slot& slot,
                                       std::vector<std::uint32_t>& first) {
  std::vector<FaceId> faces = incident;
  if (std::is_sorted(faces.begin(), faces.end()))
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  else
    sort_unique_ids(faces);
  std::vector<std::uint32_t> corner_slot;  // per live face of `faces`, its corners' slots
  corner_slot.reserve(3 * faces.size());
  first.assign(count + 1, 0);
  for (const FaceId f : faces) {
    if (f.index >= mesh.face_slots() || mesh.is_deleted(f)) continue;
    const Triangle& t = mesh.face(f);
    for (int k = 0; k < 3; ++k) {
      auto s = static_cast<std::uint32_t>(slot(t[k]));
      // A face counts once for a candidate it uses at two corners.
      if (s < count && ((k > 0 && t[0] == t[k]) || (k > 1 && t[1] == t[k]))) s = kInvalidIndex;
      corner_slot.push_back(s);
      if (s < count) ++first[s + 1];
    }
  }
  for (std::size_t s = 0; s < count; ++s) first[s + 1] += first[s];
  std::vector<FaceId> around(first.back());
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  std::size_t c = 0;
  for (const FaceId f : faces) {
    if (f.index >= mesh.face_slots() || mesh.is_deleted(f)) continue;
    for (int k = 0; k < 3; ++k, ++c)
      if (corner_slot[c] < count) around[fill[corner_slot[c]]++] = f;
  }
  return around;
}

// The candidates sorted and unique, each with the live faces around it in id order: candidate
// s's are around[first[s], first[s + 1]). `slots` (reset here) maps each candidate to s.
struct CandidateFans {
  std::vector<VertexId> sorted;
  std::vector<std::uint32_t> first;
  std::vector<FaceId> around;
  std::vector<std::uint32_t> parent;                              // find_fans' forest
  std::vector<std::pair<std::uint32_t, std::uint32_t>> by_other;  // (other vertex, face slot in fs)

  /// Candidate v's place in `sorted` (its size for a vertex that is none).
  auto slot_of(const VertexSlots& slots) const {
    return [&slots, n = sorted.size()](VertexId v) {
      const std::uint32_t s = slots.get(v.index);
      return s == VertexSlots::kNone ? n : static_cast<std::size_t>(s);
    };
  }
  CandidateFans(const SurfaceMesh& mesh, const std::vector<VertexId>& candidates,
                const std::vector<FaceId>& incident, VertexSlots& slots)
      : sorted(candidates) {
    if (!std::is_sorted(sorted.begin(), sorted.end())) std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    // Candidate -> its position in `sorted` (the copies split_vertex makes are none).
    slots.reset(mesh.vertex_count());
    for (std::size_t s = 0; s < sorted.size(); ++s)
      if (sorted[s].index < mesh.vertex_count()) slots.set(sorted[s].index, static_cast<std::uint32_t>(s));
    around = faces_by_candidate(mesh, incident, sorted.size(), slot_of(slots), first);
  }
  /// Whether candidate s's faces (as `mesh` has them now) form two fans or more; `forest`: with
  /// the fans in `parent` (find_fans) when they do.
  bool pinched(const SurfaceMesh& mesh, std::size_t s, bool forest) {
    const std::size_t size = first[s + 1] - first[s];
    return size >= 2 && find_fans(mesh, sorted[s], around.data() + first[s], size, forest, parent, by_other);
  }
};

}  // namespace

bool any_pinched(const SurfaceMesh& mesh, const std::vector<VertexId>& candidates,
                 const std::vector<FaceId>& incident) {
  if (candidates.empty()) return false;
  CandidateFans fans(mesh, candidates, incident, VertexSlots::scratch());
  for (std::size_t s = 0; s < fans.sorted.size(); ++s)
    if (fans.pinched(mesh, s, false)) return true;
  return false;
}

PinchSplits split_pinched_vertices(MeshEditor& editor, const std::vector<VertexId>& candidates,
                                   const std::vector<FaceId>& incident) {
  PinchSplits out;
  if (candidates.empty()) return out;
  SurfaceMesh& mesh = editor.mesh();
  VertexSlots& slots = VertexSlots::scratch();
  CandidateFans fans(mesh, candidates, incident, slots);
  const std::vector<VertexId>& sorted = fans.sorted;
  const std::vector<std::uint32_t>& first = fans.first;
  std::vector<FaceId>& around = fans.around;
  const auto slot = fans.slot_of(slots);
  const glm::vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  std::vector<std::uint32_t> fan_copy;
  std::vector<std::uint32_t>& parent = fans.parent;  // the fans of the candidate being split
  for (std::size_t s = 0; s < sorted.size(); ++s) {
    const VertexId v = sorted[s];
    const FaceId* fs_begin = around.data() + first[s];
    const std::size_t fs_size = first[s + 1] - first[s];
    if (!fans.pinched(mesh, s, true)) continue;
    auto fs = [&](std::size_t i) { return fs_begin[i]; };
    // fs is in id order, so fan roots are each fan's lowest face; fan 0 keeps v.
    const std::size_t before = out.replaced.size();
    fan_copy.assign(fs_size, kInvalidIndex);
    for (std::uint32_t i = 0; i < fs_size; ++i) {
      const std::uint32_t r = find_root(parent, i);
      if (r == 0) continue;
      if (fan_copy[r] == kInvalidIndex) {
        const VertexId c = editor.split_vertex(v);
        fan_copy[r] = c.index;
        out.copies.emplace_back(v, c);
      }
      const FaceId f = fs(i);
      Triangle t = mesh.face(f);
      for (VertexId& w : t)
        if (w == v) w = VertexId(fan_copy[r]);
      editor.remove_face(f);
      const FaceId g = editor.add_face_from(t, f, {e[0], e[1], e[2]});
      out.replaced.emplace_back(f, g);
      // Later candidates on this face now see it under its new id.
      for (const VertexId w : t) {
        const std::size_t o = slot(w);
        if (o <= s || o >= sorted.size()) continue;
        FaceId* const list = around.data() + first[o];
        FaceId* const end = around.data() + first[o + 1];
        FaceId* const it = std::lower_bound(list, end, f);
        if (it != end && *it == f) {
          std::copy(it + 1, end, it);
          end[-1] = g;  // g is the newest face: the list stays in id order
        }
      }
    }
    for (std::uint32_t i = 0; i < fs_size; ++i)
      if (find_root(parent, i) == 0) out.around.push_back(fs(i));
    for (std::size_t r = before; r < out.replaced.size(); ++r) out.around.push_back(out.replaced[r].second);
  }
  return out;
}

void follow_pinch_splits(const SurfaceMesh& mesh, const PinchSplits& splits, std::vector<VertexId>& chain, bool closed) {
  if (splits.copies.empty() || chain.size() < 2) return;
  std::unordered_map<std::uint32_t, std::uint32_t> original;  // copy -> original, original -> itself
  for (const auto& [v, c] : splits.copies) {
    original.emplace(c.index, v.index);
    original.emplace(v.index, v.index);
  }
  auto base = [&](VertexId v) {
    const auto it = original.find(v.index);
    return it == original.end() ? v.index : it->second;
  };
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  // Halfedges around the split vertices, by the originals of their ends.
  std::unordered_map<std::uint64_t, std::vector<std::pair<VertexId, VertexId>>> halfedges;
  for (const FaceId f : splits.around) {
    if (mesh.is_deleted(f)) continue;
    const Triangle& t = mesh.face(f);
    for (int k = 0; k < 3; ++k) halfedges[key(base(t[k]), base(t[(k + 1) % 3]))].emplace_back(t[k], t[(k + 1) % 3]);
  }
  const std::size_t n = chain.size();
  std::vector<VertexId> out = chain;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = base(chain[i]);
    if (!original.count(b)) continue;
    std::vector<VertexId> from_next, from_prev;
    if (closed || i + 1 < n) {
      const auto it = halfedges.find(key(b, base(chain[(i + 1) % n])));
      if (it != halfedges.end())
        for (const auto& [x, y] : it->second) from_next.push_back(x);
    }
    if (closed || i > 0) {
      const auto it = halfedges.find(key(base(chain[(i + n - 1) % n]), b));
      if (it != halfedges.end())
        for (const auto& [x, y] : it->second) from_prev.push_back(y);
    }
    VertexId pick;
    for (const VertexId x : from_next)
      if (!pick.valid() && std::find(from_prev.begin(), from_prev.end(), x) != from_prev.end()) pick = x;
    if (!pick.valid() && !from_next.empty()) pick = from_next.front();
    if (!pick.valid() && !from_prev.empty()) pick = from_prev.front();
    if (pick.valid()) out[i] = pick;
  }
  chain.swap(out);
}

}  // namespace deepcut::detail
