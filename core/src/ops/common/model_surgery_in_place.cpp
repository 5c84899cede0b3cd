// SPDX-License-Identifier: MIT
#include "ops/common/model_surgery_in_place.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/process_memory.h"
#include "ops/common/model_surgery.h"

namespace deepcut::detail {

const AttributeSet& set_of(const SurfaceMesh& mesh, int kind) {
  return kind == 0 ? mesh.vertex_attrs() : kind == 1 ? mesh.face_attrs() : mesh.corner_attrs();
}
AttributeSet& set_of(SurfaceMesh& mesh, int kind) {
  return kind == 0 ? mesh.vertex_attrs() : kind == 1 ? mesh.face_attrs() : mesh.corner_attrs();
}

namespace {

constexpr std::size_t kCopyGrain = 16384;  // groups per copy job

// An array's storage as bytes (contiguous: AttributeArray holds a std::vector). The arrays
// written are the surgery's own: those of the mesh it takes apart or puts back together.
const unsigned char* bytes_of(const AttributeArrayBase& array) {
  return array.size() == 0 ? nullptr : static_cast<const unsigned char*>(array.element_data(0));
}
unsigned char* bytes_of(AttributeArrayBase& array) {
  return const_cast<unsigned char*>(bytes_of(static_cast<const AttributeArrayBase&>(array)));
}

// Run by run: consecutive groups (keep[i + 1] == keep[i] + 1, as the pieces of a mesh stored in
// spatial order come) in one memmove, which in place gives what copying group by group in that
// order gives; a lone group by a copy of fixed width (W 0: `width` bytes).
template <std::size_t W>
void copy_fixed(const GroupCopy& c) {
  const std::size_t w = W ? W : c.width;
  if (!c.spread) {
    for (std::size_t i = c.begin; i < c.end;) {
      std::size_t j = i + 1;
      while (j < c.end && c.keep[j] == c.keep[j - 1] + 1) ++j;
      if (j - i == 1) std::memcpy(c.dst + i * w, c.src + std::size_t{c.keep[i]} * w, W ? W : w);
      else std::memmove(c.dst + i * w, c.src + std::size_t{c.keep[i]} * w, (j - i) * w);
      i = j;
    }
    return;
  }
  for (std::size_t j = c.end; j > c.begin;) {
    std::size_t i = j - 1;
    while (i > c.begin && c.keep[i - 1] + 1 == c.keep[i]) --i;
    if (j - i == 1) std::memcpy(c.dst + std::size_t{c.keep[i]} * w, c.src + i * w, W ? W : w);
    else std::memmove(c.dst + std::size_t{c.keep[i]} * w, c.src + i * w, (j - i) * w);
    j = i;
  }
}

void copy_groups(const GroupCopy& c) {
  switch (c.width) {
    case 1: return copy_fixed<1>(c);
    case 2: return copy_fixed<2>(c);
    case 4: return copy_fixed<4>(c);
    case 8: return copy_fixed<8>(c);
    case 12: return copy_fixed<12>(c);
    case 16: return copy_fixed<16>(c);
    case 24: return copy_fixed<24>(c);
    case 36: return copy_fixed<36>(c);
    case 48: return copy_fixed<48>(c);
    default: return copy_fixed<0>(c);
  }
}

// `copy` over groups [begin, end), as jobs of kCopyGrain groups appended to `jobs`.
void add_chunks(GroupCopy copy, std::size_t begin, std::size_t end, std::vector<GroupCopy>& jobs) {
  for (std::size_t b = begin; b < end; b += kCopyGrain) {
    copy.begin = b;
    copy.end = std::min(end, b + kCopyGrain);
    jobs.push_back(copy);
  }
}

// The jobs over the pool (they write disjoint bytes, so the result is the same in any order).
void run_copies(const std::vector<GroupCopy>& jobs) {
  run_chunks(jobs.size(), [&](std::size_t i) { copy_groups(jobs[i]); });
}

// A stretch of an in-place gather or spread by an increasing `keep` (so keep[i] >= i).
struct Step {
  std::size_t begin, end;
  bool parallel;  // copied by chunks at once; else by one job, in order
};

// The stretches of the in-place gather by `keep`, in the order they run. Every group a stretch
// starting at i reads lies at or beyond keep[i], so a stretch no longer than keep[i] - i reads
// nothing it writes and its chunks may run at once; shorter reaches are copied in order. The
// leading run that stays put is not copied.
std::vector<Step> gather_steps(const std::vector<std::uint32_t>& keep) {
  std::vector<Step> out;
  for (std::size_t i = staying_put(keep); i < keep.size();) {
    const std::size_t reach = keep[i] - i;
    const bool parallel = reach >= 2 * kCopyGrain;
    const std::size_t end = std::min(keep.size(), i + (parallel ? reach : 2 * kCopyGrain));
    out.push_back({i, end, parallel});
    i = end;
  }
  return out;
}

// The stretches of the in-place spread by `keep`, in the order they run: from the end. A stretch
// [b, e) with keep[b] >= e writes only at or beyond e, past every group it reads, so its chunks
// may run at once; where no such stretch is long enough, 2 * kCopyGrain groups are copied
// backward by one job. The leading run that stays put is not copied.
std::vector<Step> spread_steps(const std::vector<std::uint32_t>& keep) {
  std::vector<Step> out;
  const std::size_t first = staying_put(keep);
  for (std::size_t e = keep.size(); e > first;) {
    const auto from = keep.begin() + static_cast<std::ptrdiff_t>(first);
    std::size_t b = static_cast<std::size_t>(std::lower_bound(from, keep.begin() + static_cast<std::ptrdiff_t>(e), e) -
                                             keep.begin());
    const bool parallel = e - b >= 2 * kCopyGrain;
    if (!parallel) b = e - std::min(e - first, 2 * kCopyGrain);
    out.push_back({b, e, parallel});
    e = b;
  }
  return out;
}

// Every array of `mesh` (its triangles included) to gather (`spread` false) or spread in place
// by `vertices` and `faces`: stretch by stretch, each over every array at once.
MovePlan plan_moves(SurfaceMesh& mesh, const std::vector<std::uint32_t>& vertices,
                    const std::vector<std::uint32_t>& faces, bool spread) {
  std::vector<Triangle>& tris = TrustedAssign::faces(mesh);
  auto steps_of = [&](const std::vector<std::uint32_t>& keep) {
    return spread ? spread_steps(keep) : gather_steps(keep);
  };
  const std::vector<Step> steps[2] = {steps_of(vertices), steps_of(faces)};
  MovePlan plan;
  plan.rounds.resize(std::max(steps[0].size(), steps[1].size()));
  for (std::size_t r = 0; r < plan.rounds.size(); ++r) {
    std::vector<GroupCopy>& jobs = plan.rounds[r];
    auto add = [&](unsigned char* bytes, std::size_t width, const std::vector<std::uint32_t>& keep, const Step& step) {
      const GroupCopy copy{bytes, bytes, width, keep.data(), step.begin, step.end, spread};
      if (step.parallel) add_chunks(copy, step.begin, step.end, jobs);
      else jobs.push_back(copy);
    };
    for (int kind = 0; kind < 3; ++kind) {
      const std::vector<Step>& list = steps[kind == 0 ? 0 : 1];
      if (r >= list.size()) continue;
      AttributeSet& set = set_of(mesh, kind);
      for (const std::string& name : set.names()) {
        AttributeArrayBase& array = *set.base(name);
        add(bytes_of(array), array.element_bytes() * group_of(kind), kind == 0 ? vertices : faces, list[r]);
      }
    }
    if (r < steps[1].size()) add(reinterpret_cast<unsigned char*>(tris.data()), sizeof(Triangle), faces, steps[1][r]);
  }
  return plan;
}

// The plan's rounds, one after the other (allocates nothing).
void run_moves(const MovePlan& plan) {
  for (const std::vector<GroupCopy>& jobs : plan.rounds) run_copies(jobs);
}

// The mesh's arrays, as they are now, made its content again (sizes as the sets say).
void reassign(SurfaceMesh& mesh) {
  std::vector<Triangle>& tris = TrustedAssign::faces(mesh);
  TrustedAssign::assign(mesh, std::move(tris), std::move(mesh.vertex_attrs()), std::move(mesh.face_attrs()),
                        std::move(mesh.corner_attrs()));
}

// The pages of `mesh`'s arrays past the room (split_room) of its `vertices` and `faces` (its
// sizes, assigned) handed back to the system: a piece compacted in place keeps its mesh's
// capacity, and the bytes past the piece held the mesh's elements (the deleted marks too, which
// assign_trusted rewrites only up to the piece's faces), so without this every page of the mesh
// stayed resident as long as the piece lived. The room an operation on the piece grows into
// stays; growing the piece back into its mesh (expand_piece, an undo) faults the rest in again.
// Allocates nothing (AttributeSet::release_room loops over its arrays' flat list).
void release_past_room(SurfaceMesh& mesh, std::size_t vertices, std::size_t faces) noexcept {
  const std::size_t vertex_room = split_room(vertices), face_room = split_room(faces);
  for (int kind = 0; kind < 3; ++kind)
    set_of(mesh, kind).release_room((kind == 0 ? vertex_room : face_room) * group_of(kind));
  release_room(TrustedAssign::faces(mesh), face_room);
  release_room(TrustedAssign::deleted(mesh), face_room);
}

}  // namespace

std::size_t staying_put(const std::vector<std::uint32_t>& keep) {
  // keep[i] - i never decreases, so the run is found by bisection.
  std::size_t lo = 0, hi = keep.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (keep[mid] == mid) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

MovePlan plan_compaction(SurfaceMesh& mesh, const std::vector<std::uint32_t>& vertices,
                         const std::vector<std::uint32_t>& faces) {
  return plan_moves(mesh, vertices, faces, false);
}

void compact_piece(SurfaceMesh& mesh, const MovePlan& plan, const std::vector<std::uint32_t>& vertices,
                   const std::vector<std::uint32_t>& faces, const std::uint32_t* rank) {
  run_moves(plan);
  std::vector<Triangle>& tris = TrustedAssign::faces(mesh);
  tris.resize(faces.size());
  parallel_for(tris.size(), kIndexGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (VertexId& v : tris[i]) v = VertexId(rank[v.index]);
  });
  for (int kind = 0; kind < 3; ++kind)
    set_of(mesh, kind).resize((kind == 0 ? vertices : faces).size() * group_of(kind));
  reassign(mesh);
  release_past_room(mesh, vertices.size(), faces.size());
}

namespace {

// `array` (of kind `kind`, named `name`) grown to `n` elements: by copies of the rooms' elements
// where they have the array and make up the growth exactly, else by default values.
void grow_array(AttributeArrayBase& array, int kind, const std::string& name, std::size_t n,
                const std::vector<Room>& rooms) {
  std::vector<std::pair<const AttributeArrayBase*, std::size_t>> from;  // source, groups
  std::size_t total = array.size();
  for (const Room& room : rooms) {
    const AttributeArrayBase* src = room.values[static_cast<std::size_t>(kind)]->base(name);
    const std::size_t count = (kind == 0 ? room.vertices : room.faces) * group_of(kind);
    if (!src || src->type() != array.type() || src->size() < count) return array.resize(n);
    from.emplace_back(src, count);
    total += count;
  }
  if (total != n) return array.resize(n);
  for (const auto& [src, count] : from) array.append_from(*src, 0, count);
}

}  // namespace

void expand_piece(SurfaceMesh& piece, const std::vector<std::uint32_t>& vertices,
                  const std::vector<std::uint32_t>& faces, std::size_t vertex_count, std::size_t face_slots,
                  const std::vector<Room>& rooms) {
  std::vector<Triangle>& tris = TrustedAssign::faces(piece);
  // Growing an array by default values is a slow fill the spread then overwrites: copies of the
  // elements that will come into the room (memcpy) are cheaper, one task per array (largest
  // first) over the pool.
  std::vector<std::pair<std::size_t, std::function<void()>>> grow;  // bytes written, task
  for (int kind = 0; kind < 3; ++kind) {
    const std::size_t n = (kind == 0 ? vertex_count : face_slots) * group_of(kind);
    AttributeSet& set = set_of(piece, kind);
    for (const std::string& name : set.names()) {
      AttributeArrayBase* array = set.base(name);
      grow.emplace_back(n * array->element_bytes(),
                        [array, kind, name, n, &rooms] { grow_array(*array, kind, name, n, rooms); });
    }
  }
  grow.emplace_back(face_slots * sizeof(Triangle), [&tris, face_slots, &rooms] {
    for (const Room& room : rooms)
      if (tris.size() + room.faces <= face_slots) tris.insert(tris.end(), room.triangles, room.triangles + room.faces);
    tris.resize(face_slots);
  });
  std::stable_sort(grow.begin(), grow.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  run_chunks(grow.size(), [&](std::size_t i) { grow[i].second(); });
  for (int kind = 0; kind < 3; ++kind)
    set_of(piece, kind).resize((kind == 0 ? vertex_count : face_slots) * group_of(kind));
  run_moves(plan_moves(piece, vertices, faces, true));
  const std::uint32_t* to = vertices.data();
  parallel_for(faces.size(), kIndexGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (VertexId& v : tris[faces[i]]) v = VertexId(to[v.index]);
  });
  reassign(piece);
}

void scatter(SurfaceMesh& mesh, const Elements& from, const std::vector<std::uint32_t>& vertices,
             const std::vector<std::uint32_t>& faces) {
  std::vector<GroupCopy> jobs;
  for (int kind = 0; kind < 3; ++kind) {
    const std::vector<std::uint32_t>& keep = kind == 0 ? vertices : faces;
    AttributeSet& set = set_of(mesh, kind);
    for (const std::string& name : set.names()) {
      AttributeArrayBase& array = *set.base(name);
      const AttributeArrayBase* src = from.values[static_cast<std::size_t>(kind)]->base(name);
      if (!src || src->element_bytes() != array.element_bytes())
        throw Error(ErrorCode::MissingAttribute, "scatter: attribute '" + name + "' is missing");
      if (src->size() < keep.size() * group_of(kind))
        throw Error(ErrorCode::InvalidArgument, "scatter: attribute '" + name + "' holds too few elements");
      if (keep.empty()) continue;
      add_chunks({bytes_of(array), bytes_of(*src), array.element_bytes() * group_of(kind), keep.data(), 0, 0, true}, 0,
                 keep.size(), jobs);
    }
  }
  if (from.triangle_count < faces.size())
    throw Error(ErrorCode::InvalidArgument, "scatter: too few triangles");
  run_copies(jobs);
  std::vector<Triangle>& tris = TrustedAssign::faces(mesh);
  const std::uint32_t* map = from.vertex_map ? from.vertex_map->data() : nullptr;
  parallel_for(faces.size(), kIndexGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Triangle t = from.triangles[i];
      if (map)
        for (VertexId& v : t) v = VertexId(map[v.index]);
      tris[faces[i]] = t;
    }
  });
}

}  // namespace deepcut::detail
