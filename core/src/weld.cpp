// SPDX-License-Identifier: MIT
#include "deepcut/core/weld.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "byte_rows.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/parallel.h"
#include "first_of_class.h"
#include "ops/common/model_surgery.h"

namespace deepcut {
namespace {

constexpr std::size_t kGrain = 16384;
// Every attr::morph_position_name starts so.
constexpr const char* kMorphPrefix = "v:morph";

// The vertex attributes as raw arrays (no virtual call per vertex): positions compare by value
// (+0 == -0) and hash with -0 folded into +0; every other attribute compares and hashes raw.
class VertexBytes {
 public:
  // With `with_attributes` false only the positions and the morph position deltas count
  // (WeldKey::Position): a vertex is where it is in every morph target.
  VertexBytes(const SurfaceMesh& mesh, bool with_attributes) : positions_(mesh.positions().data()) {
    const auto& va = mesh.vertex_attrs();
    if (va.size() == 0) return;
    for (const auto& name : va.names()) {
      if (name == attr::kPosition || (!with_attributes && name.rfind(kMorphPrefix, 0) != 0)) continue;
      rows_.add(*va.base(name));
    }
  }

  // The full hash, continued from the position's.
  std::uint64_t hash(std::uint32_t v, std::uint64_t seed) const { return detail::ByteRows::finish(rows_.hash(v, seed)); }
  std::uint64_t position_hash(std::uint32_t v) const {
    const glm::vec3 p = positions_[v] + glm::vec3(0.0f);  // -0 + 0 = +0
    std::uint32_t w[3];
    std::memcpy(w, &p, sizeof(w));
    using detail::ByteRows;
    return ByteRows::mix(ByteRows::mix(ByteRows::mix(ByteRows::kSeed, w[0]), w[1]), w[2]);
  }
  bool same_position(std::uint32_t u, std::uint32_t v) const { return positions_[u] == positions_[v]; }
  bool equal(std::uint32_t u, std::uint32_t v) const { return same_position(u, v) && rows_.equal(u, v); }

 private:
  const glm::vec3* positions_;
  detail::ByteRows rows_;
};

// The live faces, and the vertices in order of first use by them.
struct FaceUse {
  bool all = false;           // every face slot is live and kept (then `faces` is left empty)
  std::size_t slots = 0;      // the mesh's face slots
  detail::Indices faces;      // live face slots, in order (unless `all`)
  detail::Indices first_use;  // vertices, in order of first use by the live faces

  std::size_t size() const { return all ? slots : faces.size(); }
  std::uint32_t face(std::size_t i) const { return all ? static_cast<std::uint32_t>(i) : faces[i]; }
};

// When the corners of faces [0, nf) name the vertices in order of first use (each corner's
// vertex at most one past the largest before it: 0, 1, 2, 0, 2, 3, ...), the number of vertices
// they use (vertices 0 .. n - 1; none past them), else 0. Files written vertex by vertex as their
// faces first use them (DeepCut's own, many exporters') are so. One pass over the corners in
// parallel chunks: each chunk notes one past its largest vertex (`top`) and the largest vertex it
// names past one more than the largest of its own before it (`need`: the chunks before it must
// reach one less); the chunks are then checked in order.
std::size_t used_in_first_use_order(const std::vector<Triangle>& tris, std::size_t nf) {
  struct Chunk {
    std::uint32_t top = 0, need = 0;  // need 0: none (vertex 0 is always allowed)
  };
  const std::size_t chunks = (nf + kGrain - 1) / kGrain;
  std::vector<Chunk> parts(chunks);
  parallel_for(nf, kGrain, [&](std::size_t b, std::size_t e) {
    std::uint32_t top = 0, need = 0;  // vertex indices are below 2^32 - 1 (kInvalidIndex)
    for (std::size_t f = b; f < e; ++f)
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t v = tris[f][k].index;
        need = std::max(need, v > top ? v : 0u);
        top = std::max(top, v + 1);
      }
    parts[b / kGrain] = {top, need};
  });
  std::uint32_t top = 0;
  for (const Chunk& c : parts) {
    if (c.need > top) return 0;
    top = std::max(top, c.top);
  }
  return top;
}

// When every face slot is live and the faces name their vertices in order of first use
// (used_in_first_use_order): `use.first_use` set to 0, 1, ... and true. Else false, `use` as it was.
bool first_uses_in_order(const std::vector<Triangle>& tris, FaceUse& use) {
  if (!use.all) return false;
  const std::size_t used = used_in_first_use_order(tris, use.size());
  if (used == 0) return false;
  use.first_use.resize(used);
  parallel_for(used, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) use.first_use[v] = static_cast<std::uint32_t>(v);
  });
  return true;
}

// In parallel: each vertex's first corner (an atomic minimum over the corners using it), then
// the vertices whose first corner each face holds, face by face: counted per chunk of faces, a
// prefix sum, then each chunk of faces writes its own range. Faces that name their vertices in
// order of first use (used_in_first_use_order) need neither.
FaceUse first_uses(const SurfaceMesh& mesh) {
  FaceUse use;
  const auto& tris = mesh.faces();
  use.all = mesh.face_count() == tris.size();  // as read from a file: no face deleted, no list of them
  use.slots = tris.size();
  if (!use.all)
    use.faces = detail::ordered_indices(tris.size(), [&](std::size_t f) { return !mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))); });
  if (first_uses_in_order(tris, use)) return use;
  const std::size_t nf = use.size();
  std::unique_ptr<std::atomic<std::uint32_t>[]> first(new std::atomic<std::uint32_t>[mesh.vertex_count()]);
  parallel_for(mesh.vertex_count(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) first[v].store(kInvalidIndex, std::memory_order_relaxed);
  });
  parallel_for(nf, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const Triangle& t = tris[use.face(i)];
      for (std::uint32_t k = 0; k < 3; ++k) {
        const auto c = static_cast<std::uint32_t>(3 * i + k);
        std::atomic<std::uint32_t>& slot = first[t[k].index];
        std::uint32_t s = slot.load(std::memory_order_relaxed);
        while (c < s && !slot.compare_exchange_weak(s, c, std::memory_order_relaxed)) {
        }
      }
    }
  });
  // Calls emit(v) for each corner of faces [b, e) that is its vertex v's first, in order.
  auto firsts = [&](std::size_t b, std::size_t e, auto&& emit) {
    for (std::size_t i = b; i < e; ++i) {
      const Triangle& t = tris[use.face(i)];
      for (std::uint32_t k = 0; k < 3; ++k)
        if (first[t[k].index].load(std::memory_order_relaxed) == 3 * i + k) emit(t[k].index);
    }
  };
  // How many first corners each chunk of faces holds, counted over the vertices (each used
  // vertex's first corner names its chunk), a sixth of the work of counting over the corners.
  const std::size_t chunks = (nf + kGrain - 1) / kGrain;
  std::vector<std::size_t> start = parallel_reduce(
      mesh.vertex_count(), kGrain, std::vector<std::size_t>(chunks + 1, 0),
      [&](std::size_t b, std::size_t e) {
        std::vector<std::size_t> n(chunks + 1, 0);
        for (std::size_t v = b; v < e; ++v) {
          const std::uint32_t c = first[v].load(std::memory_order_relaxed);
          if (c != kInvalidIndex) ++n[c / (3 * kGrain) + 1];
        }
        return n;
      },
      [](std::vector<std::size_t> a, const std::vector<std::size_t>& b) {
        for (std::size_t c = 0; c < a.size(); ++c) a[c] += b[c];
        return a;
      });
  for (std::size_t c = 0; c < chunks; ++c) start[c + 1] += start[c];
  use.first_use.resize(start[chunks]);
  parallel_for(nf, kGrain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* out = use.first_use.data() + start[b / kGrain];
    firsts(b, e, [&out](std::uint32_t v) { *out++ = v; });
  });
  return use;
}

// The welded vertices: old vertex -> new vertex, and new vertex -> its representative.
struct Classes {
  detail::Indices to_new;             // kInvalidIndex for a vertex no face uses
  std::vector<std::uint32_t> keep;    // new vertex -> old representative (its first user)
  std::size_t kept_apart = 0;
};

// The classes of `items` (vertices, in first-use order) by `hash` and `same`.
template <class Items, class Hash, class Same>
detail::Indices classes_of(const Items& items, Hash&& hash_of, Same&& same) {
  detail::UninitVector<std::uint64_t> hash(items.size());
  parallel_for(items.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) hash[i] = hash_of(items[i]);
  });
  return detail::first_of_class(hash, [&](std::uint32_t a, std::uint32_t b) { return same(items[a], items[b]); });
}

// The classes of `items` (vertices) by position alone.
template <class Items>
detail::Indices position_classes(const VertexBytes& bytes, const Items& items) {
  return classes_of(
      items, [&](std::uint32_t v) { return detail::ByteRows::finish(bytes.position_hash(v)); },
      [&](std::uint32_t u, std::uint32_t v) { return bytes.same_position(u, v); });
}

// How many items lead their class (first[i] == i).
std::size_t count_leaders(const detail::Indices& first) {
  return parallel_reduce(
      first.size(), kGrain, std::size_t(0),
      [&](std::size_t b, std::size_t e) {
        std::size_t n = 0;
        for (std::size_t i = b; i < e; ++i) n += first[i] == i;
        return n;
      },
      [](std::size_t a, std::size_t b) { return a + b; });
}

// For every used vertex (in first-use order), the first one with its whole key. Vertices are
// grouped by position first: nearly always the vertices at one position share the rest of
// their key too, so the position classes are the classes, which one pass over the few merged
// vertices confirms (no hash of the rest of the key, and no vertex is kept apart). Otherwise
// they are grouped again by the whole key. `*kept_apart` gets the classes less the positions.
detail::Indices first_of_key(const VertexBytes& bytes, const detail::Indices& first_use, std::size_t* kept_apart) {
  const std::size_t nu = first_use.size();
  const detail::Indices by_position = position_classes(bytes, first_use);
  const int split = parallel_reduce(
      nu, kGrain, 0,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          if (by_position[i] != i && !bytes.equal(first_use[i], first_use[by_position[i]])) return 1;
        return 0;
      },
      [](int a, int b) { return a | b; });
  *kept_apart = 0;
  if (!split) return by_position;
  detail::Indices first = classes_of(
      first_use, [&](std::uint32_t v) { return bytes.hash(v, bytes.position_hash(v)); },
      [&](std::uint32_t u, std::uint32_t v) { return bytes.equal(u, v); });
  *kept_apart = count_leaders(first) - count_leaders(by_position);
  return first;
}

// Representatives that share a position with an earlier one: all of them less the positions.
std::size_t count_kept_apart(const VertexBytes& bytes, const std::vector<std::uint32_t>& keep) {
  return keep.size() - count_leaders(position_classes(bytes, keep));
}

// Keying every used vertex, in first-use order, so the first user of a class is its
// representative (its bytes, e.g. the sign of a zero coordinate, are the ones kept). The classes
// are found in parallel (first_of_key) and numbered in first-use order.
Classes classify(const VertexBytes& bytes, const detail::Indices& first_use, std::size_t nv, WeldKey key) {
  Classes out;
  out.to_new.resize(nv);
  parallel_for(nv, kGrain, [&](std::size_t b, std::size_t e) { std::fill(out.to_new.begin() + b, out.to_new.begin() + e, kInvalidIndex); });
  const std::size_t nu = first_use.size();
  if (key == WeldKey::None) {
    out.keep.assign(first_use.begin(), first_use.end());
    parallel_for(nu, kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) out.to_new[first_use[i]] = static_cast<std::uint32_t>(i);
    });
    return out;
  }
  std::size_t kept_apart = 0;
  const detail::Indices first = first_of_key(bytes, first_use, &kept_apart);
  const detail::Indices reps = detail::ordered_indices(nu, [&](std::size_t i) { return first[i] == i; });
  detail::Indices id(nu);  // read only at each class's first item, which the loop below sets
  out.keep.resize(reps.size());
  parallel_for(reps.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      id[reps[k]] = static_cast<std::uint32_t>(k);
      out.keep[k] = first_use[reps[k]];
    }
  });
  parallel_for(nu, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) out.to_new[first_use[i]] = id[first[i]];
  });
  if (key == WeldKey::PositionAndSkin) out.kept_apart = kept_apart;
  return out;
}

// Drops the live faces whose corners fall on one welded vertex and renumbers the welded
// vertices by first use in the faces left; vertices only dropped faces used go.
// @returns the number of faces dropped.
std::size_t drop_repeating_faces(const std::vector<Triangle>& in_faces, FaceUse& use, Classes& classes) {
  auto repeats = [&](std::uint32_t f) {
    const Triangle& t = in_faces[f];
    const std::uint32_t w[3] = {classes.to_new[t[0].index], classes.to_new[t[1].index], classes.to_new[t[2].index]};
    return w[0] == w[1] || w[1] == w[2] || w[0] == w[2];
  };
  // Usually none repeats (checked in parallel): the classes are then already numbered by first
  // use in the faces (classify numbers them by their first user) and nothing changes.
  const int any = parallel_reduce(
      use.size(), kGrain, 0,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          if (repeats(use.face(i))) return 1;
        return 0;
      },
      [](int a, int b) { return a | b; });
  if (!any) return 0;
  detail::Indices faces;
  faces.reserve(use.size());
  std::vector<std::uint32_t> renumber(classes.keep.size(), kInvalidIndex), keep;
  for (std::size_t i = 0; i < use.size(); ++i) {
    const std::uint32_t f = use.face(i);
    if (repeats(f)) continue;
    const Triangle& t = in_faces[f];
    const std::uint32_t w[3] = {classes.to_new[t[0].index], classes.to_new[t[1].index], classes.to_new[t[2].index]};
    faces.push_back(f);
    for (const std::uint32_t c : w)
      if (renumber[c] == kInvalidIndex) {
        renumber[c] = static_cast<std::uint32_t>(keep.size());
        keep.push_back(classes.keep[c]);
      }
  }
  const std::size_t dropped = use.size() - faces.size();
  use.faces = std::move(faces);
  use.all = false;
  for (std::uint32_t& to : classes.to_new)
    if (to != kInvalidIndex) to = renumber[to];
  classes.keep = std::move(keep);
  return dropped;
}

// The representatives' vertex attributes (`keep`), one array per thread of the pool, each
// appended run by run (gather_groups: never value-initialised) into memory with the room that
// operations get (operation_room.h), so reserving that room after the import copies nothing.
// As the import builds its arrays (ArrayBuild, which wants typed std::vectors): the room is
// reserved on the calling thread, whose heap keeps freed memory for the next weld
// (keep_freed_memory; a worker's would map and unmap an array over 64 MiB alone), and the pages
// the elements take are faulted in from there over the whole pool (prefault); inside the tasks a
// prefault would run serially on each task's thread.
AttributeSet gather_vertices(const AttributeSet& in, const std::vector<std::uint32_t>& keep) {
  const std::vector<std::string> names = in.names();
  std::vector<std::unique_ptr<AttributeArrayBase>> arrays(names.size());
  std::vector<std::function<void()>> tasks;
  for (std::size_t i = 0; i < names.size(); ++i) {
    arrays[i] = in.base(names[i])->clone_subset({});  // empty, of the same type and default
    arrays[i]->reserve(operation_vertex_room(keep.size()));
    if (!keep.empty()) {  // one element for a pointer to the room, dropped again (the capacity stays)
      arrays[i]->resize(1);
      detail::prefault(const_cast<void*>(arrays[i]->element_data(0)),
                       keep.size() * arrays[i]->element_bytes());
      arrays[i]->resize(0);
    }
    tasks.push_back([&, i] { in.base(names[i])->gather_groups(*arrays[i], keep, 1, nullptr); });
  }
  parallel_invoke(tasks);
  AttributeSet out;
  out.resize(keep.size());
  for (std::size_t i = 0; i < names.size(); ++i) out.put(names[i], std::move(arrays[i]));
  return out;
}

// The kept faces renumbered to the welded vertices. When every face is kept (`use.all`) they are
// renumbered in place, in the mesh's own array (no new memory to fault in), which gets the room
// that operations get if it lacks it; otherwise copied into a new array with that room.
std::vector<Triangle> welded_faces(SurfaceMesh& mesh, const FaceUse& use, const Classes& classes) {
  const auto& to_new = classes.to_new;
  auto welded = [&](const Triangle& t) {
    return Triangle{VertexId(to_new[t[0].index]), VertexId(to_new[t[1].index]), VertexId(to_new[t[2].index])};
  };
  std::vector<Triangle> faces;
  if (use.all && !mesh.observer()) {
    faces = std::move(detail::TrustedAssign::faces(mesh));  // the mesh is assigned anew right after
    parallel_for(faces.size(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) faces[i] = welded(faces[i]);
    });
    faces.reserve(operation_face_room(faces.size()));
    return faces;
  }
  const auto& in_faces = mesh.faces();
  detail::resize_prefaulted(faces, use.size(), Triangle(), operation_face_room(use.size()));
  parallel_for(faces.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) faces[i] = welded(in_faces[use.face(i)]);
  });
  return faces;
}

// The mesh rebuilt from the kept faces, their corners and the representatives' vertex attributes.
void rebuild(SurfaceMesh& mesh, const FaceUse& use, const Classes& classes) {
  const bool faces_deleted = use.size() != mesh.faces().size();
  std::vector<Triangle> faces = welded_faces(mesh, use, classes);
  // The attribute sets leave the mesh (no copy) and come back gathered.
  AttributeSet vattrs = gather_vertices(mesh.vertex_attrs(), classes.keep), fattrs = std::move(mesh.face_attrs()),
               cattrs = std::move(mesh.corner_attrs());
  if (faces_deleted) {
    std::vector<std::uint32_t> corners(3 * use.faces.size());
    for (std::size_t i = 0; i < use.faces.size(); ++i)
      for (std::uint32_t k = 0; k < 3; ++k) corners[3 * i + k] = 3 * use.faces[i] + k;
    fattrs.gather(std::vector<std::uint32_t>(use.faces.begin(), use.faces.end()));
    cattrs.gather(corners);
  }
  // Every index is a welded vertex (to_new): the check of each against the vertex count is skipped.
  detail::TrustedAssign::assign(mesh, std::move(faces), std::move(vattrs), std::move(fattrs), std::move(cattrs));
}

}  // namespace

WeldReport weld(SurfaceMesh& mesh, const WeldOptions& options) {
  WeldReport report;
  const VertexBytes bytes(mesh, options.key == WeldKey::PositionAndSkin);
  const std::size_t nv = mesh.vertex_count();
  FaceUse use = first_uses(mesh);
  Classes classes = classify(bytes, use.first_use, nv, options.key);
  report.kept_apart = classes.kept_apart;
  std::size_t used = use.first_use.size();
  if (options.drop_repeating_faces) {
    report.faces_dropped = drop_repeating_faces(mesh.faces(), use, classes);
    if (report.faces_dropped) {
      used = 0;
      for (const std::uint32_t to : classes.to_new) used += to != kInvalidIndex;
      if (options.key == WeldKey::PositionAndSkin) report.kept_apart = count_kept_apart(bytes, classes.keep);
    }
  }
  report.dropped = nv - used;
  report.merged = used - classes.keep.size();
  rebuild(mesh, use, classes);
  return report;
}

}  // namespace deepcut
