// SPDX-License-Identifier: MIT
#include "ops/common/model_surgery.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include "deepcut/core/parallel.h"
#include "ops/common/model_surgery_in_place.h"
#include "side_by_side.h"
#include "uninit_vector.h"

namespace deepcut::detail {

SurfaceMesh extract(const SurfaceMesh& mesh, const std::vector<FaceId>& faces) {
  // What a copy with every other face deleted, compacted, holds (faces and vertices in id
  // order), gathered straight from `mesh`: the cost follows `faces`, not the mesh, so a drill's
  // wall or a small piece comes out in time proportional to its own size.
  std::vector<std::uint32_t> keep_faces;
  keep_faces.reserve(faces.size());
  for (FaceId f : faces)
    if (!mesh.is_deleted(f)) keep_faces.push_back(f.index);
  std::sort(keep_faces.begin(), keep_faces.end());
  keep_faces.erase(std::unique(keep_faces.begin(), keep_faces.end()), keep_faces.end());
  std::vector<std::uint32_t> keep_vertices, keep_corners;
  keep_vertices.reserve(3 * keep_faces.size());
  keep_corners.reserve(3 * keep_faces.size());
  for (std::uint32_t f : keep_faces)
    for (int k = 0; k < 3; ++k) {
      keep_vertices.push_back(mesh.face(FaceId(f))[k].index);
      keep_corners.push_back(3 * f + static_cast<std::uint32_t>(k));
    }
  std::sort(keep_vertices.begin(), keep_vertices.end());
  keep_vertices.erase(std::unique(keep_vertices.begin(), keep_vertices.end()), keep_vertices.end());
  auto new_index = [&](VertexId v) {
    return VertexId(static_cast<std::uint32_t>(
        std::lower_bound(keep_vertices.begin(), keep_vertices.end(), v.index) - keep_vertices.begin()));
  };
  std::vector<Triangle> tris;
  tris.reserve(keep_faces.size());
  for (std::uint32_t f : keep_faces) {
    const Triangle& t = mesh.face(FaceId(f));
    tris.push_back({new_index(t[0]), new_index(t[1]), new_index(t[2])});
  }
  SurfaceMesh out;
  out.assign(std::move(tris), mesh.vertex_attrs().subset(keep_vertices), mesh.face_attrs().subset(keep_faces),
             mesh.corner_attrs().subset(keep_corners));
  return out;
}

namespace {

constexpr std::size_t kGrain = 65536;
constexpr std::uint32_t kNoList = kInvalidIndex;

// Live faces of `faces`, increasing, each once: the faces extract() keeps. A cut's lists are so
// already: one pass that only reads says so, then they are copied whole (no append per face).
std::vector<std::uint32_t> live_increasing(const SurfaceMesh& mesh, const std::vector<FaceId>& faces) {
  bool kept_as_is = true;
  for (std::size_t i = 0; i < faces.size(); ++i)
    kept_as_is &= !mesh.is_deleted(faces[i]) && (i == 0 || faces[i - 1].index < faces[i].index);
  std::vector<std::uint32_t> out;
  if (kept_as_is) {
    out.resize(faces.size());
    std::transform(faces.begin(), faces.end(), out.begin(), [](FaceId f) { return f.index; });
    return out;
  }
  out.reserve(faces.size());
  for (FaceId f : faces)
    if (!mesh.is_deleted(f)) out.push_back(f.index);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

using Marks = std::unique_ptr<std::atomic<std::uint32_t>[]>;

// The list using each vertex (kNoList: none), marked by its faces, list after list (plain
// stores, any order within a list). A vertex marked for an earlier list when a later one reaches
// it is used by both: `shared` is set then (exactly when the lists share a vertex).
Marks mark_vertices(const SurfaceMesh& mesh, const std::vector<std::vector<std::uint32_t>>& faces, bool& shared) {
  const std::size_t nv = mesh.vertex_count();
  Marks marks(new std::atomic<std::uint32_t>[nv]);
  parallel_for(nv, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) marks[v].store(kNoList, std::memory_order_relaxed);
  });
  std::atomic<bool> clash{false};
  for (std::size_t s = 0; s < faces.size(); ++s) {
    const auto list = static_cast<std::uint32_t>(s);
    parallel_for(faces[s].size(), kGrain, [&](std::size_t b, std::size_t e) {
      bool seen = false;
      for (std::size_t i = b; i < e; ++i)
        for (VertexId v : mesh.face(FaceId(faces[s][i]))) {
          const std::uint32_t was = marks[v.index].load(std::memory_order_relaxed);
          seen |= was != kNoList && was != list;
          marks[v.index].store(list, std::memory_order_relaxed);
        }
      if (seen) clash.store(true, std::memory_order_relaxed);
    });
  }
  shared = clash.load();
  return marks;
}

// Each list's vertices, increasing, and every used vertex's index in its list (`list_of(v)`: the
// list using vertex v, kNoList for none; an unused vertex's rank is left unset, never read):
// chunks count per list, then fill from their running offsets (the same numbers whatever the
// chunks).
template <class ListOf>
void number_vertices(const ListOf& list_of, std::size_t nv, std::size_t lists, std::vector<std::vector<std::uint32_t>>& keep,
                     UninitVector<std::uint32_t>& rank) {
  const std::size_t grain = grain_per_thread(nv, kGrain);
  const std::size_t chunks = std::max<std::size_t>(1, (nv + grain - 1) / grain);
  std::vector<std::uint32_t> start(chunks * lists, 0);
  parallel_for(nv, grain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* count = &start[b / grain * lists];
    for (std::size_t v = b; v < e; ++v) {
      const std::uint32_t s = list_of(v);
      if (s != kNoList) ++count[s];
    }
  });
  keep.assign(lists, {});
  std::vector<std::uint32_t> totals(lists, 0);
  for (std::size_t s = 0; s < lists; ++s) {
    std::uint32_t total = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::uint32_t count = start[c * lists + s];
      start[c * lists + s] = total;
      total += count;
    }
    totals[s] = total;
  }
  size_side_by_side(
      lists, [&](std::size_t s) -> std::vector<std::uint32_t>& { return keep[s]; },
      [&](std::size_t s) { return totals[s]; });
  rank.resize(nv);
  parallel_for(nv, grain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* next = &start[b / grain * lists];
    for (std::size_t v = b; v < e; ++v) {
      const std::uint32_t s = list_of(v);
      if (s == kNoList) continue;
      rank[v] = next[s]++;
      keep[s][rank[v]] = static_cast<std::uint32_t>(v);
    }
  });
}

// What the pieces keep of the mesh: per list its faces and vertices (increasing; a face's
// corners follow it) and its triangles renumbered.
struct Numbering {
  std::vector<std::vector<std::uint32_t>> faces, vertices;
  UninitVector<std::uint32_t> rank;  // each used vertex's index in its list (only theirs are written)
  std::vector<std::vector<Triangle>> tris;
};

// The triangles `fs` renumbered by `rank` (the lists use disjoint vertices), written once into new
// memory: reserved, then appended to, no value-initialisation first.
void number_faces(const SurfaceMesh& mesh, const std::vector<std::uint32_t>& fs, const UninitVector<std::uint32_t>& rank,
                  std::vector<Triangle>& tris) {
  tris.reserve(fs.size());
  for (std::uint32_t f : fs) {
    const Triangle& t = mesh.face(FaceId(f));
    tris.push_back({VertexId(rank[t[0].index]), VertexId(rank[t[1].index]), VertexId(rank[t[2].index])});
  }
}

std::uint32_t index_of(FaceId f) { return f.index; }
std::uint32_t index_of(std::uint32_t f) { return f; }

// Whether every list is live and increasing (as live_increasing leaves it) and every face's
// corners lie on its list's side (list_of_side[side + 1] == list: what the cut's vertex sides
// promise; a face that broke it would be renumbered through a rank never written). The lists are
// a cut's FaceIds, copied into `faces` as they are checked (reserved on the calling thread, its
// heap, and sized side by side, a list a task: size_side_by_side; unspecified when false), or
// `faces` itself, indices sorted by live_increasing, only checked. In chunks over the pool, in
// one job.
template <class Id>
bool live_increasing_on_sides(const SurfaceMesh& mesh, const std::vector<std::vector<Id>>& lists,
                              const std::int8_t* side, const std::uint32_t* list_of_side,
                              std::vector<std::vector<std::uint32_t>>& faces) {
  constexpr bool copy = std::is_same_v<Id, FaceId>;
  struct Chunk {
    std::size_t list, begin, end;
  };
  std::vector<Chunk> chunks;
  if constexpr (copy) {
    size_side_by_side(
        lists.size(), [&](std::size_t s) -> std::vector<std::uint32_t>& { return faces[s]; },
        [&](std::size_t s) { return lists[s].size(); });
  }
  for (std::size_t s = 0; s < lists.size(); ++s) {
    for (std::size_t b = 0; b < lists[s].size(); b += kGrain)
      chunks.push_back({s, b, std::min(lists[s].size(), b + kGrain)});
  }
  // The side value each list's corners must have (list_of_side[side + 1] == list): none (a value
  // no vertex has) for a list no side picks.
  std::vector<int> wanted(lists.size(), 2);
  for (int v = -1; v <= 1; ++v)
    if (list_of_side[v + 1] < lists.size()) wanted[list_of_side[v + 1]] = v;
  std::atomic<bool> broken{false};
  run_chunks(chunks.size(), [&](std::size_t c) {
    const Chunk& k = chunks[c];
    const Id* list = lists[k.list].data();
    [[maybe_unused]] std::uint32_t* to = faces[k.list].data();
    const int want = wanted[k.list];
    std::int64_t last = k.begin == 0 ? -1 : std::int64_t{index_of(list[k.begin - 1])};
    bool bad = false;
    for (std::size_t i = k.begin; i < k.end; ++i) {
      const std::uint32_t f = index_of(list[i]);
      const Triangle& t = mesh.face(FaceId(f));
      bad |= (std::int64_t{f} <= last) | mesh.is_deleted(FaceId(f)) | (side[t[0].index] != want) |
             (side[t[1].index] != want) | (side[t[2].index] != want);
      if constexpr (copy) to[i] = f;
      last = f;
    }
    if (bad) broken.store(true, std::memory_order_relaxed);
  });
  return !broken.load();
}

// Every list's faces and vertices numbered (out.tris is filled by fill_pieces). The list using
// each vertex is read from `sides` when given, else marked by the lists' faces. False when the
// lists share vertices.
bool number_pieces(const SurfaceMesh& mesh, const std::vector<std::vector<FaceId>>& lists, const PieceSides* sides,
                   Numbering& out) {
  const std::size_t n = lists.size();
  if (n >= kNoList) return false;
  out.faces.resize(n);
  out.tris.resize(n);
  const std::size_t nv = mesh.vertex_count();
  std::uint32_t list_of_side[3] = {kNoList, kNoList, kNoList};  // side -1, 0, +1
  if (sides)
    for (std::size_t s = 0; s < n; ++s) list_of_side[(*sides->list_sides)[s] > 0 ? 2 : 0] = static_cast<std::uint32_t>(s);
  const std::int8_t* side = sides ? sides->vertex_sides->data() : nullptr;
  // A cut's lists as the cut makes them (live, increasing, each face's corners on its list's
  // side) are read once: checked and copied in one pass over the pool. Other lists are made live
  // and increasing first; the sides still number them when their faces lie on them (the sides
  // keep every vertex on a list's side, also one only a deleted face used; marking drops it).
  bool on_sides = sides && live_increasing_on_sides(mesh, lists, side, list_of_side, out.faces);
  if (!on_sides) {
    std::vector<std::function<void()>> tasks;
    for (std::size_t s = 0; s < n; ++s)
      tasks.emplace_back([&, s] { out.faces[s] = live_increasing(mesh, lists[s]); });
    parallel_invoke(tasks);
    on_sides = sides && live_increasing_on_sides(mesh, out.faces, side, list_of_side, out.faces);
  }
  if (on_sides) {
    const std::uint32_t* list_by_side = list_of_side + 1;  // indexed by the side itself
    number_vertices([&](std::size_t v) { return list_by_side[side[v]]; }, nv, n, out.vertices, out.rank);
    return true;
  }
  bool shared = false;
  const Marks owner = mark_vertices(mesh, out.faces, shared);
  if (shared) return false;
  number_vertices([&](std::size_t v) { return owner[v].load(std::memory_order_relaxed); }, nv, n, out.vertices, out.rank);
  return true;
}

// --- the pieces' arrays ------------------------------------------------------------------------
// Groups of elements are copied: a vertex's or a face's element, or a face's three corners (side
// by side). A piece copied out is new memory, or the memory of a step being dropped (give_room):
// each of its arrays is written once, by one task (fill_pieces, through
// AttributeArrayBase::gather_groups). The piece that keeps the mesh's arrays is compacted in place
// (compact_piece).

// The list that picks a set's elements (faces pick their corners too).
const std::vector<std::uint32_t>& list_of(const Numbering& num, std::size_t s, int kind) {
  return kind == 0 ? num.vertices[s] : num.faces[s];
}

// Bytes of a vertex's and of a face's attributes (its corners' and its triangle included).
std::pair<std::size_t, std::size_t> element_bytes(const SurfaceMesh& mesh) {
  std::size_t vertex = 0, face = sizeof(Triangle);
  for (int kind = 0; kind < 3; ++kind)
    for (const std::string& name : set_of(mesh, kind).names())
      (kind == 0 ? vertex : face) += set_of(mesh, kind).base(name)->element_bytes() * group_of(kind);
  return {vertex, face};
}

// The piece that keeps the mesh's arrays: the one that saves the most copying. A piece copied out
// costs about twice its bytes (new memory is touched, then written); the one compacted in place
// costs the bytes it moves, those past its leading run that stays put (staying_put). So the
// piece with the most bytes plus bytes in place, the first of equals; none without faces.
std::size_t in_place_piece(const SurfaceMesh& mesh, const Numbering& num) {
  const auto [vertex_bytes, face_bytes] = element_bytes(mesh);
  const std::size_t n = num.faces.size();
  std::size_t best = n, best_gain = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (num.faces[s].empty()) continue;
    const std::size_t gain = vertex_bytes * (num.vertices[s].size() + staying_put(num.vertices[s])) +
                             face_bytes * (num.faces[s].size() + staying_put(num.faces[s]));
    if (best == n || gain > best_gain) {
      best = s;
      best_gain = gain;
    }
  }
  return best;
}

// One array of a piece copied out: where from, where to, which groups.
struct ArrayCopy {
  const AttributeArrayBase* from;
  AttributeArrayBase* to;
  const std::vector<std::uint32_t>* keep;
  std::size_t group;
  int kind;  // 0 vertices, 1 faces, 2 corners
};

// Room for the arrays of the pieces copied out of a watched mesh (a session's, edited further):
// each takes a spare that fits (SplitWatcher::spare_array), else new memory with a piece's room
// (split_room, reserved, not touched), so an operation on the piece finds room, and so
// does a next cut's piece a little larger than this one, copied into it once this step is dropped.
// A spare may hold up to twice that room (a piece's own room fits it, however small the piece).
void give_room(SplitWatcher& watcher, std::vector<ArrayCopy>& copies, Numbering& num, std::size_t big) {
  for (ArrayCopy& c : copies) {
    const std::size_t count = c.keep->size();
    const std::size_t room = c.group * split_room(count);
    if (std::unique_ptr<AttributeArrayBase> spare = watcher.spare_array(*c.to, count * c.group, 2 * room))
      c.to->take_room(*spare);
    else
      c.to->reserve(room);
  }
  for (std::size_t s = 0; s < num.faces.size(); ++s) {
    if (s == big) continue;
    const std::size_t room = split_room(num.faces[s].size());
    num.tris[s] = watcher.spare_triangles(num.faces[s].size(), 2 * room);
    if (num.tris[s].capacity() < num.faces[s].size()) num.tris[s].reserve(room);
  }
}

// The attribute sets of every piece but `big` (3 per piece: vertices, faces, corners), copied
// out of `mesh`, and every piece's triangles (number_faces): each array filled by its own task
// (gather_groups, number_faces; largest first), into the room give_room makes when `watcher`
// follows the split, else into new memory of exactly their size.
std::vector<AttributeSet> fill_pieces(const SurfaceMesh& mesh, Numbering& num, std::size_t big,
                                      SplitWatcher* watcher) {
  const std::size_t n = num.faces.size();
  std::vector<AttributeSet> sets(3 * n);
  std::vector<ArrayCopy> copies;
  for (std::size_t s = 0; s < n; ++s)
    for (int kind = 0; kind < 3 && s != big; ++kind) {
      AttributeSet& set = sets[3 * s + static_cast<std::size_t>(kind)];
      set = set_of(mesh, kind).subset({});
      for (const std::string& name : set.names())
        copies.push_back(
            {set_of(mesh, kind).base(name), set.base(name), &list_of(num, s, kind), group_of(kind), kind});
    }
  if (watcher) {
    give_room(*watcher, copies, num, big);
  } else {
    // Reserved here, on the calling thread, exactly as the tasks would (gather_groups and
    // number_faces find their room made): every array comes from the caller's heap (arena),
    // whichever thread fills it. Reserved on the pool's threads, each array came from the heap
    // of the thread that happened to take its task, and a thread's heap that held less than the
    // pieces it took this time grew into fresh pages (faults) at a cost that moved from call to
    // call.
    for (ArrayCopy& c : copies) c.to->reserve(c.keep->size() * c.group);
    for (std::size_t s = 0; s < n; ++s)
      if (s != big) num.tris[s].reserve(num.faces[s].size());
  }
  std::vector<std::pair<std::size_t, std::function<void()>>> tasks;  // bytes written, task
  for (ArrayCopy& c : copies)
    tasks.emplace_back(c.keep->size() * c.group * c.from->element_bytes(),
                       [&c] { c.from->gather_groups(*c.to, *c.keep, c.group, nullptr); });
  for (std::size_t s = 0; s < n; ++s)
    if (s != big)
      tasks.emplace_back(num.faces[s].size() * sizeof(Triangle),
                         [&, s] { number_faces(mesh, num.faces[s], num.rank, num.tris[s]); });
  std::stable_sort(tasks.begin(), tasks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  run_chunks(tasks.size(), [&](std::size_t i) { tasks[i].second(); });
  for (std::size_t s = 0; s < n; ++s)
    for (int kind = 0; kind < 3 && s != big; ++kind)  // the sets' own counts (their arrays have them)
      sets[3 * s + static_cast<std::size_t>(kind)].resize(list_of(num, s, kind).size() * group_of(kind));
  return sets;
}

// The pieces `lists` of `mesh`; with `owned` (`mesh` itself, to take apart) the piece that keeps
// the mesh's arrays (in_place_piece) is compacted in place once the others are copied out.
std::vector<SurfaceMesh> make_pieces(const SurfaceMesh& mesh, const std::vector<std::vector<FaceId>>& lists,
                                     SurfaceMesh* owned, const PieceSides* sides = nullptr,
                                     std::vector<PieceElements>* elements = nullptr) {
  const std::size_t n = lists.size();
  std::vector<SurfaceMesh> out(n);
  Numbering num;
  if (!number_pieces(mesh, lists, sides, num)) {
    std::vector<std::function<void()>> tasks;
    for (std::size_t s = 0; s < n; ++s) tasks.emplace_back([&, s] { out[s] = extract(mesh, lists[s]); });
    parallel_invoke(tasks);
    return out;
  }
  std::size_t big = owned ? in_place_piece(mesh, num) : n;
  // A watched mesh is taken apart only when its watcher follows it through the split; it is told
  // once the other pieces are copied out, right before the compaction.
  SplitWatcher* watcher = big < n && owned->observer() ? dynamic_cast<SplitWatcher*>(owned->observer()) : nullptr;
  const std::uint32_t watched_as = owned ? owned->observer_id() : 0;
  if (big < n && owned->observer() && !(watcher && watcher->accepts(watched_as, *owned))) {
    big = n;
    watcher = nullptr;
  }
  std::vector<AttributeSet> sets = fill_pieces(mesh, num, big, watcher);
  for (std::size_t s = 0; s < n; ++s)
    if (s != big)
      TrustedAssign::assign(out[s], std::move(num.tris[s]), std::move(sets[3 * s]), std::move(sets[3 * s + 1]),
                            std::move(sets[3 * s + 2]));
  // Every allocation of the compaction is made before the watcher is told: from then on the mesh
  // is taken apart without a failure that could leave it half compacted.
  const MovePlan plan = big < n ? plan_compaction(*owned, num.vertices[big], num.faces[big]) : MovePlan{};
  if (watcher) watcher->splitting(watched_as, *owned, num.vertices, num.faces, big);
  if (big < n) {
    compact_piece(*owned, plan, num.vertices[big], num.faces[big], num.rank.data());
    out[big] = std::move(*owned);
  }
  if (watcher) watcher->split(watched_as, out);
  if (elements) {
    elements->resize(n);
    for (std::size_t s = 0; s < n; ++s) (*elements)[s] = {std::move(num.vertices[s]), std::move(num.faces[s])};
  }
  return out;
}

}  // namespace

std::vector<SurfaceMesh> extract_disjoint(const SurfaceMesh& mesh, const std::vector<std::vector<FaceId>>& lists) {
  return make_pieces(mesh, lists, nullptr);
}

std::vector<SurfaceMesh> split_disjoint(SurfaceMesh&& mesh, const std::vector<std::vector<FaceId>>& lists) {
  return make_pieces(mesh, lists, &mesh);
}

std::vector<SurfaceMesh> split_disjoint(SurfaceMesh&& mesh, const std::vector<std::vector<FaceId>>& lists,
                                        const PieceSides& sides, std::vector<PieceElements>* elements) {
  const std::vector<int>* list_sides = sides.list_sides;
  const bool usable = sides.vertex_sides && list_sides && sides.vertex_sides->size() == mesh.vertex_count() &&
                      list_sides->size() == lists.size() && lists.size() <= 2 &&
                      (lists.size() < 2 || (*list_sides)[0] != (*list_sides)[1]);
  return make_pieces(mesh, lists, &mesh, usable ? &sides : nullptr, elements);
}

int cut_surface_material(Model& model) {
  for (std::size_t i = 0; i < model.materials.size(); ++i)
    if (model.materials[i].name == "Cut surface") return static_cast<int>(i);
  model.materials.push_back(
      {"Cut surface",
       R"({"name":"Cut surface","doubleSided":false,"pbrMetallicRoughness":)"
       R"({"baseColorFactor":[0.8,0.18,0.16,1.0],"metallicFactor":0.0,"roughnessFactor":0.9}})"});
  return static_cast<int>(model.materials.size() - 1);
}

std::string unique_node_name(const Model& model, const std::string& wanted) {
  auto taken = [&](const std::string& name) {
    return std::any_of(model.nodes.begin(), model.nodes.end(), [&](const Node& n) { return n.name == name; });
  };
  if (!taken(wanted)) return wanted;
  for (int i = 2;; ++i)
    if (!taken(wanted + "_" + std::to_string(i))) return wanted + "_" + std::to_string(i);
}

namespace {

// A mesh made from `source`'s primitives (a cut's piece) keeps its morph targets' defaults and
// names: the primitives carry the targets' deltas as vertex attributes already.
void inherit_morph_targets(const Mesh& source, Mesh& mesh) {
  if (mesh.weights.empty()) mesh.weights = source.weights;
  if (mesh.target_names.empty()) mesh.target_names = source.target_names;
}

// Every channel animating the morph weights of node `from` also animates node `to` (same
// sampler), so a piece plays the expression its source node plays.
void copy_weight_channels(Model& model, int from, int to) {
  for (Animation& anim : model.animations) {
    const std::size_t count = anim.channels.size();
    for (std::size_t c = 0; c < count; ++c)
      if (anim.channels[c].node == from && anim.channels[c].path == AnimationPath::Weights) {
        AnimationChannel copy = anim.channels[c];
        copy.node = to;
        anim.channels.push_back(copy);
      }
  }
}

// Node `node` no longer draws a mesh: weights on it (node.weights, weight channels) would
// describe targets it does not have, which glTF forbids.
void drop_weights(Model& model, int node) {
  model.nodes[static_cast<std::size_t>(node)].weights.clear();
  for (Animation& anim : model.animations)
    anim.channels.erase(std::remove_if(anim.channels.begin(), anim.channels.end(),
                                       [&](const AnimationChannel& ch) {
                                         return ch.node == node && ch.path == AnimationPath::Weights;
                                       }),
                        anim.channels.end());
}

}  // namespace

bool InstanceEdit::shared() const { return surgery_.users(mesh_) > 1; }

const Mesh& InstanceEdit::source() const { return surgery_.model_.meshes[static_cast<std::size_t>(mesh_)]; }

Mesh& InstanceEdit::edit() {
  if (!shared()) return surgery_.model_.meshes[static_cast<std::size_t>(mesh_)];
  if (!copied_) {
    copy_ = source();
    copied_ = true;
  }
  return copy_;
}

PosedMesh* InstanceEdit::posed(int primitive) { return surgery_.posed_.find(node_, primitive); }

PosedModel& InstanceEdit::posed_model() { return surgery_.posed_; }

Model& InstanceEdit::model() { return surgery_.model_; }

void InstanceEdit::erase_primitive(int primitive) {
  auto& prims = edit().primitives;
  prims.erase(prims.begin() + primitive);
  surgery_.posed_.erase_primitive(node_, primitive);
}

void InstanceEdit::add_primitive(Primitive primitive) {
  auto& prims = edit().primitives;
  added_primitives_.push_back(static_cast<int>(prims.size()));
  prims.push_back(std::move(primitive));
}

void InstanceEdit::drop() { dropped_ = true; }

void InstanceEdit::replace_mesh(Mesh mesh) {
  Model& model = surgery_.model_;
  inherit_morph_targets(source(), mesh);
  auto& users = surgery_.users_;
  int target = mesh_;
  if (users[static_cast<std::size_t>(mesh_)] == 1) {
    model.meshes[static_cast<std::size_t>(mesh_)] = std::move(mesh);
  } else {
    --users[static_cast<std::size_t>(mesh_)];
    model.meshes.push_back(std::move(mesh));
    users.push_back(1);
    target = static_cast<int>(model.meshes.size() - 1);
  }
  model.nodes[static_cast<std::size_t>(node_)].mesh = target;
  replaced_ = true;
}

int InstanceEdit::add_piece_node(Mesh mesh, const std::string& name) {
  Model& model = surgery_.model_;
  inherit_morph_targets(source(), mesh);
  model.meshes.push_back(std::move(mesh));
  surgery_.users_.push_back(1);
  Node node = model.nodes[static_cast<std::size_t>(node_)];  // its morph weights included
  node.children.clear();
  node.camera = -1;
  node.name = unique_node_name(model, name);
  node.mesh = static_cast<int>(model.meshes.size() - 1);
  const int index = static_cast<int>(model.nodes.size());
  model.nodes.push_back(std::move(node));
  const int parent = surgery_.parents_[static_cast<std::size_t>(node_)];
  if (parent >= 0) {
    model.nodes[static_cast<std::size_t>(parent)].children.push_back(index);
  } else {
    for (auto& roots : model.scenes)
      if (std::find(roots.begin(), roots.end(), node_) != roots.end()) roots.push_back(index);
  }
  copy_weight_channels(model, node_, index);
  surgery_.posed_.add_piece_node(node_, index);
  return index;
}

ModelSurgery::ModelSurgery(Model& model, PosedModel& posed)
    : model_(model), posed_(posed), users_(model.meshes.size(), 0), parents_(model.parents()) {
  for (const auto& n : model.nodes)
    if (n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < model.meshes.size())
      ++users_[static_cast<std::size_t>(n.mesh)];
}

void ModelSurgery::for_each_instance(const std::function<bool(InstanceEdit&)>& fn) {
  const std::size_t node_count = model_.nodes.size();
  for (std::size_t ni = 0; ni < node_count; ++ni) {
    const int mi = model_.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model_.meshes.size()) continue;
    InstanceEdit edit(*this, static_cast<int>(ni), mi);
    const bool edited = fn(edit);
    if (edit.dropped_) {
      drop_instance(edit.node_);
    } else if (edit.replaced_) {
      posed_.erase_node(edit.node_);
    } else if (edited) {
      finish(edit);
    }
  }
}

void ModelSurgery::finish(InstanceEdit& edit) {
  if (edit.copied_) {
    --users_[static_cast<std::size_t>(edit.mesh_)];
    model_.meshes.push_back(std::move(edit.copy_));
    users_.push_back(1);
    const int target = static_cast<int>(model_.meshes.size() - 1);
    model_.nodes[static_cast<std::size_t>(edit.node_)].mesh = target;
    posed_.rename_mesh(edit.node_, target);
  }
  for (int p : edit.added_primitives_) posed_.add(model_, edit.node_, p);
}

void ModelSurgery::drop_instance(int node) {
  Node& n = model_.nodes[static_cast<std::size_t>(node)];
  if (--users_[static_cast<std::size_t>(n.mesh)] == 0)
    model_.meshes[static_cast<std::size_t>(n.mesh)].primitives.clear();
  n.mesh = -1;
  n.skin = -1;
  drop_weights(model_, node);
  posed_.erase_node(node);
}

void for_each_instance(Model& model, PosedModel& posed, const std::function<bool(InstanceEdit&)>& fn) {
  ModelSurgery(model, posed).for_each_instance(fn);
}

}  // namespace deepcut::detail
