// SPDX-License-Identifier: MIT
// The copying build of the view data (ViewPolyData's constructor from a source and the step's
// PrimitiveOrigin): a piece's corners keep the points their source corners had, in passes over
// the pool, and only the corners around the rim of the step take points anew. Its own file: one
// idea apart from the full build and the updates (view_poly_data.cpp), whose Writer
// (view_poly_data_writer.h) and point assignment it uses.

#include <algorithm>
#include <atomic>
#include <memory>

#include "deepcut/core/flags.h"
#include "deepcut/core/parallel.h"
#include "view_poly_data_writer.h"

namespace deepcut {

using view_data::clear_point;
using view_data::kGrain;
using view_data::raw;
using view_data::Raw;

// What a copying build knows of a piece's corners between its passes (copy_corner_points).
struct ViewPolyData::Copying {
  std::vector<std::uint32_t> kept;     // new point -> the source's point
  std::unique_ptr<std::uint32_t[]> number;  // the source's point -> new point (kInvalidIndex: unused)
  std::vector<std::uint32_t> waiting;  // corners without a point, in order
  std::vector<char> orphan;            // per new point: no corner chosen yet
  std::vector<char> rim;               // per vertex: some corner of it waits
  std::vector<std::uint32_t> orphan_corners, rim_corners;  // their corners, in order
};

namespace {

// The number of chunks of kGrain elements among `n`.
std::size_t chunk_count(std::size_t n) { return (n + kGrain - 1) / kGrain; }

// Calls `fn(chunk, begin, end)` for `n` elements in chunks of kGrain, over the pool (results
// kept per chunk join in order). @returns the number of chunks. The bodies copy the captures
// they read into locals first, so that their stores cannot make those be read again per corner.
template <class Fn>
std::size_t for_chunks(std::size_t n, const Fn& fn) {
  const std::size_t chunks = chunk_count(n);
  parallel_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) fn(i, i * kGrain, std::min(n, (i + 1) * kGrain));
  });
  return chunks;
}

template <class T>
void join(const std::vector<std::vector<T>>& parts, std::vector<T>& out) {
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
}

// The points among `n` that are `used`, numbered in order: `number` (point -> its number, else
// kInvalidIndex) and `kept` (number -> point). Counted per chunk, then numbered from each chunk's
// first number, over the pool.
void number_in_order(const std::atomic<std::uint8_t>* used, std::size_t n,
                     std::unique_ptr<std::uint32_t[]>& number, std::vector<std::uint32_t>& kept) {
  const std::size_t chunks = chunk_count(n);
  std::vector<std::uint32_t> first(chunks + 1, 0);
  for_chunks(n, [&](std::size_t i, std::size_t b, std::size_t e) {
    std::uint32_t count = 0;
    for (std::size_t p = b; p < e; ++p) count += used[p].load(std::memory_order_relaxed);
    first[i + 1] = count;
  });
  for (std::size_t i = 0; i < chunks; ++i) first[i + 1] += first[i];
  number.reset(new std::uint32_t[n]);  // written whole below (no value fill first)
  kept.resize(first[chunks]);
  for_chunks(n, [&](std::size_t i, std::size_t b, std::size_t e) {
    std::uint32_t* const to_number = number.get();
    std::uint32_t* const to_kept = kept.data();
    std::uint32_t next = first[i];
    for (std::size_t p = b; p < e; ++p) {
      const bool in_use = used[p].load(std::memory_order_relaxed);
      to_number[p] = in_use ? next : kInvalidIndex;
      if (in_use) to_kept[next++] = static_cast<std::uint32_t>(p);
    }
  });
}

}  // namespace

bool ViewPolyData::copy_fits(const SurfaceMesh& mesh, const ViewPolyData& source, const PrimitiveOrigin& origin) {
  return draws_corners(mesh) && source.corners_ && origin.faces.size() == mesh.face_slots() &&
         origin.vertices.size() == mesh.vertex_count() &&
         source.uses_.size() == static_cast<std::size_t>(source.poly_->GetNumberOfPoints());
}

void ViewPolyData::copy_corner_points(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin) {
  const SurfaceMesh& mesh = w.mesh;
  Copying copying;
  copy_connectivity(w, source, origin, copying);
  choose_corners(w, source, origin, copying);
  renumber(w, copying);
  set_point_count(std::max<std::size_t>(copying.kept.size() + copying.waiting.size(), 1));  // room for the waiting
  Writer writer = w;
  writer.refresh(poly_);
  const std::size_t points = copying.kept.size();
  parallel_for(points, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const std::uint32_t c = point_corner_[p];
      writer.point(p, mesh.faces()[c / 3][static_cast<int>(c % 3)].index, c);
    }
  });
  assign_waiting(writer, copying.rim_corners);
  if (uses_.empty()) {  // a deleted face's cell needs point 0
    uses_.push_back(0);
    point_corner_.push_back(kInvalidIndex);
    clear_point(writer.r, 0);
  }
  set_point_count(uses_.size());
}

void ViewPolyData::copy_connectivity(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin,
                                     Copying& copying) {
  // A live face with a source face: each corner takes the point its source corner has (the
  // source's number for now) when that point draws the corner's source vertex; the others wait.
  // A deleted face's cell is (0, 0, 0).
  const SurfaceMesh& mesh = w.mesh;
  const std::size_t old_points = source.uses_.size();
  const auto old_cells = static_cast<std::size_t>(source.poly_->GetNumberOfCells());
  const Raw old = raw(source.poly_);
  const Flags used_points = cleared_flags(old_points, kGrain);
  std::atomic<std::uint8_t>* const used = used_points.get();
  const std::size_t parts = chunk_count(mesh.face_slots());
  std::vector<std::vector<std::uint32_t>> waits(parts), collapsed(parts);
  for_chunks(mesh.face_slots(), [&](std::size_t chunk, std::size_t b, std::size_t e) {
    vtkTypeInt64* const conn = w.r.connectivity;
    const vtkTypeInt64* const old_conn = old.connectivity;
    const vtkIdType* const old_vertex = old.vertex_id;
    const std::uint32_t* const face_from = origin.faces.data();
    const std::uint32_t* const vertex_from = origin.vertices.data();
    const Triangle* const faces = mesh.faces().data();
    std::atomic<std::uint8_t>* const in_use = used;
    std::vector<std::uint32_t>& wait = waits[chunk];
    for (std::size_t f = b; f < e; ++f) {
      vtkTypeInt64* const cell = conn + 3 * f;
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) {
        cell[0] = cell[1] = cell[2] = 0;
        continue;
      }
      const std::uint32_t from = face_from[f];
      const Triangle& t = faces[f];
      if (t[0] == t[1] && t[1] == t[2]) collapsed[chunk].push_back(static_cast<std::uint32_t>(f));
      for (std::size_t k = 0; k < 3; ++k) {
        vtkTypeInt64 p = -1;
        if (from < old_cells) {
          const vtkTypeInt64 q = old_conn[3 * std::size_t(from) + k];
          const std::uint32_t v = vertex_from[t[static_cast<int>(k)].index];
          if (q >= 0 && static_cast<std::size_t>(q) < old_points && v != kInvalidIndex && old_vertex[q] == v)
            p = q;
        }
        cell[k] = p;
        if (p >= 0)
          in_use[p].store(1, std::memory_order_relaxed);
        else
          wait.push_back(static_cast<std::uint32_t>(3 * f + k));
      }
    }
  });
  join(waits, copying.waiting);
  join(collapsed, collapsed_);  // (their cells may name one point three times, as deleted faces' do)
  number_in_order(used, old_points, copying.number, copying.kept);
}

void ViewPolyData::choose_corners(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin,
                                  Copying& copying) {
  // Each point's corner: the one its source point has, where that corner's face is this mesh's
  // too (found through the faces' sources) and draws it; the others (their source's corner on a
  // face the step removed: around the rim) are orphans, given their first corner by `renumber`.
  // The uses are counted with the lists (prepare_updates).
  const SurfaceMesh& mesh = w.mesh;
  const std::size_t slots = mesh.face_slots(), points = copying.kept.size();
  const auto old_cells = static_cast<std::size_t>(source.poly_->GetNumberOfCells());
  // Source face slot -> face slot (filled over the pool, not by a serial value fill first).
  std::unique_ptr<std::uint32_t[]> face_of(new std::uint32_t[old_cells]);
  parallel_for(old_cells, kGrain, [&](std::size_t b, std::size_t e) {
    std::fill(face_of.get() + b, face_of.get() + e, kInvalidIndex);
  });
  parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f)
      if (origin.faces[f] < old_cells && !mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))))
        face_of[origin.faces[f]] = static_cast<std::uint32_t>(f);
  });
  uses_.assign(points, 0);
  point_corner_.resize(points);
  copying.orphan.assign(points, 0);
  const vtkTypeInt64* conn = w.r.connectivity;
  parallel_for(points, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const std::uint32_t from = source.point_corner_[copying.kept[p]];
      const std::uint32_t f = from == kInvalidIndex ? kInvalidIndex : face_of[from / 3];
      const std::size_t c = 3 * std::size_t(f) + from % 3;
      const bool found = f != kInvalidIndex && conn[c] == static_cast<vtkTypeInt64>(copying.kept[p]);
      point_corner_[p] = found ? static_cast<std::uint32_t>(c) : kInvalidIndex;
      copying.orphan[p] = !found;
    }
  });
  copying.rim.assign(mesh.vertex_count(), 0);
  for (std::uint32_t c : copying.waiting) copying.rim[mesh.faces()[c / 3][static_cast<int>(c % 3)].index] = 1;
}

void ViewPolyData::renumber(const Writer& w, Copying& copying) {
  // One pass: the kept corners take their points' new numbers; the corners of orphan points and
  // of vertices with waiting corners are gathered, in order.
  const SurfaceMesh& mesh = w.mesh;
  const std::size_t parts = chunk_count(mesh.face_slots());
  std::vector<std::vector<std::uint32_t>> orphans(parts), rims(parts);
  for_chunks(mesh.face_slots(), [&](std::size_t chunk, std::size_t b, std::size_t e) {
    vtkTypeInt64* const conn = w.r.connectivity;
    const Triangle* const faces = mesh.faces().data();
    const char* const rim = copying.rim.data();
    const char* const orphan = copying.orphan.data();
    const std::uint32_t* const number = copying.number.get();
    std::vector<std::uint32_t>& orphan_list = orphans[chunk];
    std::vector<std::uint32_t>& rim_list = rims[chunk];
    for (std::size_t f = b; f < e; ++f) {
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
      const Triangle& t = faces[f];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t c = 3 * f + k;
        if (rim[t[static_cast<int>(k)].index]) rim_list.push_back(static_cast<std::uint32_t>(c));
        if (conn[c] < 0) continue;
        const std::uint32_t p = number[static_cast<std::size_t>(conn[c])];
        conn[c] = p;
        if (orphan[p]) orphan_list.push_back(static_cast<std::uint32_t>(c));
      }
    }
  });
  join(orphans, copying.orphan_corners);
  join(rims, copying.rim_corners);
  vtkTypeInt64* conn = w.r.connectivity;
  for (std::uint32_t c : copying.orphan_corners) {
    const auto p = static_cast<std::size_t>(conn[c]);
    if (point_corner_[p] == kInvalidIndex) point_corner_[p] = c;
  }
}

void ViewPolyData::assign_waiting(const Writer& w, const std::vector<std::uint32_t>& rim_corners) {
  // The corners of each vertex with waiting corners, by vertex (in corner order), then points
  // for the waiting ones.
  const SurfaceMesh& mesh = w.mesh;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> all;  // (vertex, corner)
  all.reserve(rim_corners.size());
  for (std::uint32_t c : rim_corners) all.emplace_back(mesh.faces()[c / 3][static_cast<int>(c % 3)].index, c);
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::uint32_t> corners;
  for (const auto& vc : all) corners.push_back(vc.second);
  std::vector<std::uint32_t> dead;
  for (std::size_t i = 0, j = 0; i < all.size(); i = j) {
    while (j < all.size() && all[j].first == all[i].first) ++j;
    assign_points(w, all[i].first, Corners{nullptr, kInvalidIndex, corners.data() + i, corners.data() + j}, dead);
  }
}

std::size_t ViewPolyData::room(const ViewPolyData& spare) {
  if (!spare.poly_) return 0;
  vtkCellArray* cells = spare.poly_->GetPolys();
  const vtkTypeInt64Array* offsets = cells->GetOffsetsArray64();
  const vtkTypeInt64Array* connectivity = cells->GetConnectivityArray64();
  const auto* face_ids = view_data::named<vtkIdTypeArray>(spare.poly_->GetCellData(), "face_id");
  if (!offsets || !connectivity || !face_ids) return 0;
  const auto held = std::min({connectivity->GetSize() / 3, offsets->GetSize() - 1, face_ids->GetSize()});
  return static_cast<std::size_t>(std::max<vtkIdType>(held, 0));
}

bool ViewPolyData::can_take(const ViewPolyData& spare, std::size_t slots) {
  return spare.poly_ && room(spare) >= slots;
}

}  // namespace deepcut
