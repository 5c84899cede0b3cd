// SPDX-License-Identifier: MIT
// The copying build of the view data (ViewPolyData's constructor from a source and the step's
// PrimitiveOrigin): a piece's corners keep the points their source corners had, in passes over
// the pool, and only the corners around the rim of the step take points anew. Its own file: one
// idea apart from the full build and the updates (view_poly_data.cpp), whose Writer
// (view_poly_data_writer.h) and point assignment it uses.

#include <algorithm>
#include <atomic>
#include <memory>

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
  std::vector<std::uint32_t> number;   // the source's point -> new point (kInvalidIndex: unused)
  std::vector<std::uint32_t> waiting;  // corners without a point, in order
  std::vector<char> orphan;            // per new point: no corner chosen yet
  std::vector<char> rim;               // per vertex: some corner of it waits
  std::vector<std::uint32_t> orphan_corners, rim_corners;  // their corners, in order
};

namespace {

// Calls `fn(chunk, f)` for every face slot of `mesh` that is live, in chunks of kGrain slots
// over the pool; `chunks` is set to their number (results kept per chunk join in order).
template <class Fn>
void for_live_faces(const SurfaceMesh& mesh, std::size_t& chunks, const Fn& fn) {
  const std::size_t slots = mesh.face_slots();
  chunks = (slots + kGrain - 1) / kGrain;
  parallel_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (std::size_t f = i * kGrain; f < std::min(slots, (i + 1) * kGrain); ++f)
        if (!mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) fn(i, f);
  });
}

template <class T>
void join(const std::vector<std::vector<T>>& parts, std::vector<T>& out) {
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
}

}  // namespace

bool ViewPolyData::copy_corner_points(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin) {
  const SurfaceMesh& mesh = w.mesh;
  if (!source.corners_ || origin.faces.size() != mesh.face_slots() || origin.vertices.size() != mesh.vertex_count() ||
      source.uses_.size() != static_cast<std::size_t>(source.poly_->GetNumberOfPoints()))
    return false;
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
  return true;
}

void ViewPolyData::copy_connectivity(const Writer& w, const ViewPolyData& source, const PrimitiveOrigin& origin,
                                     Copying& copying) {
  // A live face with a source face: each corner takes the point its source corner has (the
  // source's number for now) when that point draws the corner's source vertex; the others wait.
  const SurfaceMesh& mesh = w.mesh;
  const std::size_t old_points = source.uses_.size();
  const auto old_cells = static_cast<std::size_t>(source.poly_->GetNumberOfCells());
  const Raw old = raw(source.poly_);
  vtkTypeInt64* conn = w.r.connectivity;
  std::unique_ptr<std::atomic<std::uint8_t>[]> used(new std::atomic<std::uint8_t>[old_points]);
  parallel_for(old_points, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) used[p].store(0, std::memory_order_relaxed);
  });
  parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {  // a deleted face's cell: (0, 0, 0)
    for (std::size_t f = b; f < e; ++f)
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) std::fill(conn + 3 * f, conn + 3 * f + 3, 0);
  });
  std::size_t chunks = 0;
  const std::size_t parts = (mesh.face_slots() + kGrain - 1) / kGrain;
  std::vector<std::vector<std::uint32_t>> waits(parts), collapsed(parts);
  for_live_faces(mesh, chunks, [&](std::size_t chunk, std::size_t f) {
    const std::uint32_t from = origin.faces[f];
    const Triangle& t = mesh.faces()[f];
    if (t[0] == t[1] && t[1] == t[2]) collapsed[chunk].push_back(static_cast<std::uint32_t>(f));
    for (std::size_t k = 0; k < 3; ++k) {
      vtkTypeInt64 p = -1;
      if (from < old_cells) {
        const vtkTypeInt64 q = old.connectivity[3 * std::size_t(from) + k];
        const std::uint32_t v = origin.vertices[mesh.faces()[f][static_cast<int>(k)].index];
        if (q >= 0 && static_cast<std::size_t>(q) < old_points && v != kInvalidIndex && old.vertex_id[q] == v) p = q;
      }
      conn[3 * f + k] = p;
      if (p >= 0)
        used[p].store(1, std::memory_order_relaxed);
      else
        waits[chunk].push_back(static_cast<std::uint32_t>(3 * f + k));
    }
  });
  join(waits, copying.waiting);
  join(collapsed, collapsed_);  // (their cells may name one point three times, as deleted faces' do)
  // The source's points in use, numbered in order.
  copying.number.assign(old_points, kInvalidIndex);
  for (std::size_t p = 0; p < old_points; ++p)
    if (used[p].load(std::memory_order_relaxed)) {
      copying.number[p] = static_cast<std::uint32_t>(copying.kept.size());
      copying.kept.push_back(static_cast<std::uint32_t>(p));
    }
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
  std::vector<std::uint32_t> face_of(old_cells, kInvalidIndex);  // source face slot -> face slot
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
  vtkTypeInt64* conn = w.r.connectivity;
  const std::size_t parts = (mesh.face_slots() + kGrain - 1) / kGrain;
  std::vector<std::vector<std::uint32_t>> orphans(parts), rims(parts);
  std::size_t chunks = 0;
  for_live_faces(mesh, chunks, [&](std::size_t chunk, std::size_t f) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t c = 3 * f + k;
      if (copying.rim[mesh.faces()[f][static_cast<int>(k)].index]) rims[chunk].push_back(static_cast<std::uint32_t>(c));
      if (conn[c] < 0) continue;
      const std::uint32_t p = copying.number[static_cast<std::size_t>(conn[c])];
      conn[c] = p;
      if (copying.orphan[p]) orphans[chunk].push_back(static_cast<std::uint32_t>(c));
    }
  });
  join(orphans, copying.orphan_corners);
  join(rims, copying.rim_corners);
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

}  // namespace deepcut
