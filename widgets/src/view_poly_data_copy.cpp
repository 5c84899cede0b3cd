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

// What a copying build knows of a piece's corners between its passes (copy_corner_points), in a
// CopyScratch's memory kept from build to build: each build sizes and clears what it reads.
struct ViewPolyData::Copying {
  // Per source point: the first corner that takes it while the connectivity is copied
  // (kInvalidIndex: none), then its new number (kInvalidIndex: unused).
  std::unique_ptr<std::atomic<std::uint32_t>[]> point;
  std::size_t point_room = 0;
  std::vector<std::uint32_t> first;  // per chunk of source points: its first new number
  // Per chunk of faces: corners without a point, live faces whose corners are one vertex, and
  // the corners of vertices with waiting corners (rim vertices), in order.
  std::vector<std::vector<std::uint32_t>> waits, collapsed, rims;
  std::vector<std::uint32_t> rim_corners;  // the rims joined
  std::vector<char> rim;                   // per vertex: some corner of it waits

  // Ready for a build from `source_points` points of a mesh of `face_chunks` chunks of faces.
  void start(std::size_t source_points, std::size_t face_chunks);
};

ViewPolyData::CopyScratch::CopyScratch() = default;
ViewPolyData::CopyScratch::~CopyScratch() = default;

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

// Makes corner `c` the one `slot` notes unless a smaller corner is there: the first corner,
// whatever order the threads come in.
inline void take_first(std::atomic<std::uint32_t>& slot, std::uint32_t c) {
  std::uint32_t seen = slot.load(std::memory_order_relaxed);
  while (c < seen && !slot.compare_exchange_weak(seen, c, std::memory_order_relaxed)) {
  }
}

// The points among `n` that some corner took (`point`: each one's first corner, else
// kInvalidIndex), numbered in order: `point` then holds each one's number (else kInvalidIndex)
// and `corner` (number -> its first corner) is sized and written, with room for `more` (the
// points still to come). Counted per chunk, then numbered from each chunk's first number
// (`first`), over the pool. @returns how many.
std::size_t number_taken(std::atomic<std::uint32_t>* point, std::size_t n, std::vector<std::uint32_t>& first,
                         std::vector<std::uint32_t>& corner, std::size_t more) {
  const std::size_t chunks = chunk_count(n);
  first.assign(chunks + 1, 0);
  for_chunks(n, [&](std::size_t i, std::size_t b, std::size_t e) {
    const std::atomic<std::uint32_t>* const from = point;
    std::uint32_t count = 0;
    for (std::size_t p = b; p < e; ++p) count += from[p].load(std::memory_order_relaxed) != kInvalidIndex;
    first[i + 1] = count;
  });
  for (std::size_t i = 0; i < chunks; ++i) first[i + 1] += first[i];
  view_data::resize_to_write(corner, first[chunks], first[chunks] + more);  // (each entry written below)
  for_chunks(n, [&](std::size_t i, std::size_t b, std::size_t e) {
    std::atomic<std::uint32_t>* const to = point;
    std::uint32_t* const to_corner = corner.data();
    std::uint32_t next = first[i];
    for (std::size_t p = b; p < e; ++p) {
      const std::uint32_t c = to[p].load(std::memory_order_relaxed);
      if (c == kInvalidIndex) continue;
      to_corner[next] = c;
      to[p].store(next++, std::memory_order_relaxed);
    }
  });
  return first[chunks];
}

}  // namespace

void ViewPolyData::Copying::start(std::size_t source_points, std::size_t face_chunks) {
  if (point_room < source_points) {
    point.reset();                                               // (the old memory goes first)
    point_room = 0;                                              // (a failed allocation leaves none)
    point.reset(new std::atomic<std::uint32_t>[source_points]);  // cleared below
    point_room = source_points;
  }
  std::atomic<std::uint32_t>* const to = point.get();
  parallel_for(source_points, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) to[p].store(kInvalidIndex, std::memory_order_relaxed);
  });
  for (auto* lists : {&waits, &collapsed, &rims}) {
    lists->resize(face_chunks);
    for (auto& list : *lists) list.clear();
  }
  rim_corners.clear();
}

bool ViewPolyData::copy_fits(const SurfaceMesh& mesh, const ViewPolyData& source, const PrimitiveOrigin& origin) {
  return draws_corners(mesh) && source.corners_ && origin.faces.size() == mesh.face_slots() &&
         origin.vertices.size() == mesh.vertex_count() &&
         source.uses_.size() == static_cast<std::size_t>(source.poly_->GetNumberOfPoints());
}

void ViewPolyData::copy_corner_points(const Writer& w, const ViewPolyData& source,
                                      const PrimitiveOrigin& origin, CopyScratch& scratch) {
  const SurfaceMesh& mesh = w.mesh;
  if (!scratch.copying_) scratch.copying_ = std::make_unique<Copying>();
  Copying& copying = *scratch.copying_;
  copying.start(source.uses_.size(), chunk_count(mesh.face_slots()));
  copy_connectivity(w, source, origin, copying);
  std::size_t waiting = 0;  // (a point each at most: the per-point lists' room from the start)
  for (const auto& wait : copying.waits) waiting += wait.size();
  const std::size_t points =
      number_taken(copying.point.get(), source.uses_.size(), copying.first, point_corner_, waiting);
  view_data::refill(uses_, points, 0u, points + waiting);  // (counted with the lists: prepare_updates)
  copying.rim.assign(mesh.vertex_count(), 0);
  for (const auto& wait : copying.waits)
    for (std::uint32_t c : wait) copying.rim[mesh.faces()[c / 3][static_cast<int>(c % 3)].index] = 1;
  renumber(w, copying);
  set_point_count(std::max<std::size_t>(points + waiting, 1));  // room for the waiting
  Writer writer = w;
  writer.refresh(poly_);
  // Each point is drawn from its first corner (the corners of a point draw alike, bit for bit).
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
  // source's number for now; the point notes its first corner); the others wait. A deleted
  // face's cell is (0, 0, 0).
  const SurfaceMesh& mesh = w.mesh;
  const std::size_t old_points = source.uses_.size();
  const auto old_cells = static_cast<std::size_t>(source.poly_->GetNumberOfCells());
  const vtkTypeInt64* const old_connectivity =
      source.poly_->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  for_chunks(mesh.face_slots(), [&](std::size_t chunk, std::size_t b, std::size_t e) {
    vtkTypeInt64* const conn = w.r.connectivity;
    const vtkTypeInt64* const old_conn = old_connectivity;
    const std::uint32_t* const face_from = origin.faces.data();
    const Triangle* const faces = mesh.faces().data();
    std::atomic<std::uint32_t>* const first = copying.point.get();
    const std::size_t cells = old_cells, points = old_points;
    std::vector<std::uint32_t>& wait = copying.waits[chunk];
    for (std::size_t f = b; f < e; ++f) {
      vtkTypeInt64* const cell = conn + 3 * f;
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) {
        cell[0] = cell[1] = cell[2] = 0;
        continue;
      }
      const Triangle& t = faces[f];
      if (t[0] == t[1] && t[1] == t[2]) copying.collapsed[chunk].push_back(static_cast<std::uint32_t>(f));
      const std::size_t from = face_from[f];
      const auto c = static_cast<std::uint32_t>(3 * f);
      const vtkTypeInt64* const old_cell = from < cells ? old_conn + 3 * from : nullptr;
      auto corner = [&](std::uint32_t k) {  // (called three times, unrolled)
        const vtkTypeInt64 q = old_cell ? old_cell[k] : -1;
        if (static_cast<std::uint64_t>(q) < points) {  // (none: negative)
          cell[k] = q;
          take_first(first[q], c + k);
        } else {
          cell[k] = -1;
          wait.push_back(c + k);
        }
      };
      corner(0), corner(1), corner(2);
    }
  });
  join(copying.collapsed, collapsed_);  // (their cells may name one point three times, as deleted faces' do)
}

void ViewPolyData::renumber(const Writer& w, Copying& copying) {
  // One pass: the kept corners take their points' new numbers; the corners of rim vertices are
  // gathered, in order.
  const SurfaceMesh& mesh = w.mesh;
  for_chunks(mesh.face_slots(), [&](std::size_t chunk, std::size_t b, std::size_t e) {
    vtkTypeInt64* const conn = w.r.connectivity;
    const Triangle* const faces = mesh.faces().data();
    const char* const rim = copying.rim.data();
    const std::atomic<std::uint32_t>* const number = copying.point.get();
    std::vector<std::uint32_t>& rim_list = copying.rims[chunk];
    for (std::size_t f = b; f < e; ++f) {
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
      const Triangle& t = faces[f];
      auto corner = [&](int k) {  // (called three times, unrolled)
        const std::size_t c = 3 * f + static_cast<std::size_t>(k);
        if (rim[t[k].index]) rim_list.push_back(static_cast<std::uint32_t>(c));
        if (conn[c] >= 0) conn[c] = number[static_cast<std::size_t>(conn[c])].load(std::memory_order_relaxed);
      };
      corner(0), corner(1), corner(2);
    }
  });
  join(copying.rims, copying.rim_corners);
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
