// SPDX-License-Identifier: MIT
#include "deepcut/widgets/view_poly_data.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTypeInt64Array.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <functional>

#include "deepcut/core/morph.h"
#include "deepcut/core/parallel.h"
#include "corner_groups.h"

namespace deepcut {
namespace {

constexpr std::size_t kGrain = 16384;

// Sets `n` tuples, keeping the values below and room to grow (a step appends a few elements:
// no reallocation of the whole array each time).
template <class Array>
void set_count(Array* a, std::size_t n) {
  const auto tuples = static_cast<vtkIdType>(n);
  if (tuples * a->GetNumberOfComponents() > a->GetSize()) a->Resize(tuples + tuples / 8 + 1024);
  a->SetNumberOfTuples(tuples);
}

template <class Array>
Array* named(vtkDataSetAttributes* data, const char* name) {
  return Array::SafeDownCast(data->GetArray(name));
}

// The arrays of a view poly data, by raw storage (valid until the next resize).
struct Raw {
  float* points = nullptr;
  float* normals = nullptr;
  float* uv = nullptr;
  vtkIdType* vertex_id = nullptr;
  vtkIdType* face_id = nullptr;
  vtkTypeInt64* offsets = nullptr;
  vtkTypeInt64* connectivity = nullptr;
};

Raw raw(vtkPolyData* poly) {
  Raw r;
  vtkPointData* pd = poly->GetPointData();
  r.points = vtkFloatArray::SafeDownCast(poly->GetPoints()->GetData())->GetPointer(0);
  if (auto* a = vtkFloatArray::SafeDownCast(pd->GetNormals())) r.normals = a->GetPointer(0);
  if (auto* a = named<vtkFloatArray>(pd, "uv0")) r.uv = a->GetPointer(0);  // active or not
  r.vertex_id = named<vtkIdTypeArray>(pd, "vertex_id")->GetPointer(0);
  r.face_id = named<vtkIdTypeArray>(poly->GetCellData(), "face_id")->GetPointer(0);
  r.offsets = poly->GetPolys()->GetOffsetsArray64()->GetPointer(0);
  r.connectivity = poly->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  return r;
}

// Point `p`'s position and, when both are there, normal: what a build, an update and a new
// pose all write.
void write_point(const Raw& r, std::size_t p, const glm::vec3& position, const glm::vec3* normal) {
  std::copy(&position.x, &position.x + 3, r.points + 3 * p);
  if (r.normals && normal) std::copy(&normal->x, &normal->x + 3, r.normals + 3 * p);
}

// A point no corner draws (what a deleted face's cell names when no other point is left).
void clear_point(const Raw& r, std::size_t p) {
  std::fill(r.points + 3 * p, r.points + 3 * p + 3, 0.0f);
  r.vertex_id[p] = 0;
  if (r.uv) std::fill(r.uv + 2 * p, r.uv + 2 * p + 2, 0.0f);
  if (r.normals) std::fill(r.normals + 3 * p, r.normals + 3 * p + 3, 0.0f);
}

}  // namespace

// Writes elements of one state of the mesh into the arrays: the one kernel of the whole build
// and of every update.
struct ViewPolyData::Writer {
  Raw r;
  const SurfaceMesh& mesh;
  const std::vector<glm::vec3>& positions;
  const glm::vec3* normals = nullptr;  // posed corner normals, else the mesh's (or none)
  const glm::vec2* uv = nullptr;
  // What else decides a corner's normal in some pose: the mesh's normals (when posed ones are
  // drawn) and the morph normal deltas.
  std::vector<const glm::vec3*> normal_sources;

  Writer(vtkPolyData* poly, const SurfaceMesh& m, const std::vector<glm::vec3>& p,
         const std::vector<glm::vec3>* n)
      : r(raw(poly)), mesh(m), positions(p) {
    const auto& ca = m.corner_attrs();
    if (const auto* a = ca.find<glm::vec2>(attr::kUv0)) uv = a->data().data();
    const auto* own = ca.find<glm::vec3>(attr::kNormal);
    if (n && !n->empty()) {
      normals = n->data();
      if (own) normal_sources.push_back(own->data().data());
    } else if (own) {
      normals = own->data().data();
    }
    for (int t = 0, targets = morph_target_count(m); t < targets; ++t)
      if (const auto* a = ca.find<glm::vec3>(attr::morph_normal_name(t)))
        normal_sources.push_back(a->data().data());
  }

  void refresh(vtkPolyData* poly) { r = raw(poly); }

  // Corners `a` and `b` (of one vertex) draw alike in every pose: bit for bit.
  bool alike(std::size_t a, std::size_t b) const {
    auto same3 = [&](const glm::vec3* x) { return std::memcmp(&x[a], &x[b], sizeof(glm::vec3)) == 0; };
    if (normals && !same3(normals)) return false;
    if (uv && std::memcmp(&uv[a], &uv[b], sizeof(glm::vec2)) != 0) return false;
    return std::all_of(normal_sources.begin(), normal_sources.end(), same3);
  }

  // Point `p` draws vertex `v` as corner `c` does.
  void point(std::size_t p, std::uint32_t v, std::size_t c) const {
    write_point(r, p, positions[v], normals ? &normals[c] : nullptr);
    r.vertex_id[p] = v;
    if (r.uv && uv) {
      r.uv[2 * p] = uv[c].x;
      r.uv[2 * p + 1] = uv[c].y;
    }
  }

  void vertex_cell(std::size_t f) const {
    const FaceId face(static_cast<std::uint32_t>(f));
    const Triangle& t = mesh.face(face);
    const bool deleted = mesh.is_deleted(face);
    for (int k = 0; k < 3; ++k)
      r.connectivity[3 * f + static_cast<std::size_t>(k)] = deleted ? 0 : t[k].index;
  }

  void vertex_point(std::size_t v) const {
    write_point(r, v, positions[v], nullptr);
    r.vertex_id[v] = static_cast<vtkIdType>(v);
  }
};

// The points one vertex's corners use so far, each with a corner it draws like: a few, found
// without a scan of the vertex's corners; a vertex whose corners draw in more ways than that
// (`full`) is searched corner by corner for the rest (`ViewPolyData::alike_point`).
struct ViewPolyData::Candidates {
  static constexpr int kMax = 32;
  std::uint32_t point[kMax], corner[kMax];
  int n = 0;
  bool full = false;  // a point was left out
  void add(std::uint32_t p, std::uint32_t c) {
    for (int i = 0; i < n; ++i)
      if (point[i] == p) return;
    if (n < kMax)
      point[n] = p, corner[n++] = c;
    else
      full = true;
  }
  // A point corner `c` draws like, or kInvalidIndex.
  std::uint32_t find(const Writer& w, std::uint32_t c) const {
    for (int i = 0; i < n; ++i)
      if (w.alike(corner[i], c)) return point[i];
    return kInvalidIndex;
  }
};

// The corners of one vertex: its linked list (from `head` through `next`), or a list of its own.
struct ViewPolyData::Corners {
  const std::uint32_t* next = nullptr;
  std::uint32_t head = kInvalidIndex;
  const std::uint32_t *begin = nullptr, *end = nullptr;
  // Calls `fn(c)` for each corner in order until it returns true. @returns whether one did.
  template <class Fn>
  bool any(const Fn& fn) const {
    if (next) {
      for (std::uint32_t c = head; c != kInvalidIndex; c = next[c])
        if (fn(c)) return true;
      return false;
    }
    return std::any_of(begin, end, fn);
  }
};

ViewPolyData::Corners ViewPolyData::linked(std::uint32_t v) const { return {next_.data(), first_[v]}; }

std::uint32_t ViewPolyData::alike_point(const Writer& w, const Candidates& seen, const Corners& corners,
                                        std::uint32_t c, const vtkTypeInt64* conn) const {
  std::uint32_t p = seen.find(w, c);
  if (p != kInvalidIndex || !seen.full) return p;
  corners.any([&](std::uint32_t d) {
    if (d == c || conn[d] < 0 || !w.alike(d, c)) return false;
    p = static_cast<std::uint32_t>(conn[d]);
    return true;
  });
  return p;
}

ViewPolyData::ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                           const std::vector<glm::vec3>* corner_normals) {
  make_arrays(mesh);
  resize(mesh);
  vertices_ = mesh.vertex_count();
  const std::size_t slots = mesh.face_slots();
  Writer w(poly_, mesh, positions, corner_normals);
  if (corners_) {
    const CornerGroups groups = group_corners(mesh);
    build_corner_points(w, groups);
    if (groups.one_vertex_face)  // else the lists wait (link_cells reads a cell (p, p, p) as deleted)
      link_all(3 * slots, mesh.vertex_count(), [&](std::size_t c) {
        const auto f = static_cast<std::uint32_t>(c / 3);
        return mesh.is_deleted(FaceId(f)) ? kInvalidIndex : mesh.faces()[f][static_cast<int>(c % 3)].index;
      });
  } else {
    parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f < e; ++f) w.vertex_cell(f);
    });
    parallel_for(mesh.vertex_count(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v < e; ++v) w.vertex_point(v);
    });
  }
  modified();
}

ViewPolyData::ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                           const std::vector<glm::vec3>* corner_normals, const ViewPolyData& source,
                           const PrimitiveOrigin& origin) {
  make_arrays(mesh);
  resize(mesh);
  vertices_ = mesh.vertex_count();
  if (corners_ && copy_corner_points(Writer(poly_, mesh, positions, corner_normals), source, origin)) {
    copied_ = true;
    modified();
    return;
  }
  *this = ViewPolyData(mesh, positions, corner_normals);
}

void ViewPolyData::make_arrays(const SurfaceMesh& mesh) {
  const auto& ca = mesh.corner_attrs();
  const auto* uv = ca.find<glm::vec2>(attr::kUv0);
  const auto* normal = ca.find<glm::vec3>(attr::kNormal);
  corners_ = uv || normal;
  poly_ = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkFloatArray> point_data;
  point_data->SetNumberOfComponents(3);
  vtkNew<vtkPoints> points;
  points->SetData(point_data);
  poly_->SetPoints(points);
  vtkNew<vtkIdTypeArray> vertex_ids;
  vertex_ids->SetName("vertex_id");
  poly_->GetPointData()->AddArray(vertex_ids);
  if (corners_ && uv) {
    vtkNew<vtkFloatArray> a;
    a->SetName("uv0");
    a->SetNumberOfComponents(2);
    poly_->GetPointData()->SetTCoords(a);
  }
  if (corners_ && normal) {
    vtkNew<vtkFloatArray> a;
    a->SetName("normal");
    a->SetNumberOfComponents(3);
    poly_->GetPointData()->SetNormals(a);
  }
  vtkNew<vtkIdTypeArray> face_ids;
  face_ids->SetName("face_id");
  poly_->GetCellData()->AddArray(face_ids);
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkTypeInt64Array> offsets, connectivity;
  polys->SetData(offsets, connectivity);
  poly_->SetPolys(polys);
}

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

void ViewPolyData::build_corner_points(const Writer& writer, const CornerGroups& groups) {
  const std::size_t vertices = groups.offset.size() - 1;
  // Two passes over each vertex's corners: the first numbers its points from 0 (into the corners'
  // connectivity), the second adds the vertex's first point and writes the points. A deleted face's cell
  // is (0, 0, 0).
  const SurfaceMesh& mesh = writer.mesh;
  vtkTypeInt64* conn = writer.r.connectivity;
  parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f)
      std::fill(conn + 3 * f, conn + 3 * f + 3, mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))) ? 0 : -1);
  });
  const std::uint32_t* grouped = groups.corner.data();
  std::vector<std::uint32_t> first_point(vertices + 1, 0);
  parallel_for(vertices, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      Candidates seen;
      std::uint32_t count = 0;
      const Corners corners{nullptr, kInvalidIndex, grouped + groups.offset[v], grouped + groups.offset[v + 1]};
      corners.any([&](std::uint32_t c) {
        std::uint32_t p = alike_point(writer, seen, corners, c, conn);
        if (p == kInvalidIndex) seen.add(p = count++, c);
        conn[c] = p;
        return false;
      });
      first_point[v + 1] = count;
    }
  });
  for (std::size_t v = 0; v < vertices; ++v) first_point[v + 1] += first_point[v];
  const std::size_t points = first_point[vertices];
  set_point_count(std::max<std::size_t>(points, 1));  // a deleted face's cell needs point 0
  uses_.assign(std::max<std::size_t>(points, 1), 0);
  point_corner_.assign(uses_.size(), kInvalidIndex);
  Writer w = writer;
  w.refresh(poly_);
  if (points == 0) clear_point(w.r, 0);
  parallel_for(vertices, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      std::uint32_t written = 0;
      for (std::uint32_t i = groups.offset[v]; i < groups.offset[v + 1]; ++i) {
        const std::uint32_t c = grouped[i];
        const auto local = static_cast<std::uint32_t>(conn[c]);
        const std::uint32_t p = first_point[v] + local;
        w.r.connectivity[c] = p;
        ++uses_[p];
        if (local == written) {
          w.point(p, static_cast<std::uint32_t>(v), c);
          point_corner_[p] = c;
          ++written;
        }
      }
    }
  });
}

void ViewPolyData::set_point_count(std::size_t n) {
  vtkPointData* pd = poly_->GetPointData();
  set_count(vtkFloatArray::SafeDownCast(poly_->GetPoints()->GetData()), n);
  set_count(named<vtkIdTypeArray>(pd, "vertex_id"), n);
  if (auto* a = named<vtkFloatArray>(pd, "uv0")) set_count(a, n);
  if (auto* a = vtkFloatArray::SafeDownCast(pd->GetNormals())) set_count(a, n);
}

void ViewPolyData::resize(const SurfaceMesh& mesh) {
  const std::size_t slots = mesh.face_slots();
  if (!corners_) set_point_count(mesh.vertex_count());
  vtkIdTypeArray* face_ids = named<vtkIdTypeArray>(poly_->GetCellData(), "face_id");
  const auto old_cells = static_cast<std::size_t>(face_ids->GetNumberOfTuples());
  set_count(face_ids, slots);
  set_count(poly_->GetPolys()->GetOffsetsArray64(), slots + 1);
  set_count(poly_->GetPolys()->GetConnectivityArray64(), 3 * slots);
  // Every cell is a triangle: offsets and face ids of new cells are their slots.
  vtkIdType* face_id = face_ids->GetPointer(0);
  vtkTypeInt64* offsets = poly_->GetPolys()->GetOffsetsArray64()->GetPointer(0);
  const std::size_t from = std::min(old_cells, slots);
  parallel_for(slots - from, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = from + b; f < from + e; ++f) {
      face_id[f] = static_cast<vtkIdType>(f);
      offsets[f] = static_cast<vtkTypeInt64>(3 * f);
    }
  });
  offsets[slots] = static_cast<vtkTypeInt64>(3 * slots);
}

template <class VertexOf>
void ViewPolyData::link_all(std::size_t corners, std::size_t vertices, const VertexOf& vertex_of) {
  first_.assign(vertices, kInvalidIndex);
  next_.assign(corners, kInvalidIndex);
  prev_.assign(corners, kInvalidIndex);
  corner_vertex_.assign(corners, kInvalidIndex);
  // A list crosses any chunk of corners, so the work is cut by vertices: each range scans every
  // corner (from the last: `link` pushes to the front) and links those of its own vertices. The
  // lists are the same for any number of ranges; all writes of a range are to its vertices'
  // slots and their corners.
  const std::size_t ranges = std::min<std::size_t>(thread_count(), 8);
  parallel_for(ranges, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t r = b; r < e; ++r) {
      const std::size_t lo = vertices * r / ranges, hi = vertices * (r + 1) / ranges;
      for (std::size_t c = corners; c-- > 0;) {
        const std::uint32_t v = vertex_of(c);
        if (v != kInvalidIndex && v >= lo && v < hi) link(static_cast<std::uint32_t>(c), v);
      }
    }
  });
  lists_ = true;
}

void ViewPolyData::link_cells() {
  const Raw r = raw(poly_);
  const std::size_t corners = 3 * static_cast<std::size_t>(poly_->GetNumberOfCells());
  link_all(corners, vertices_, [&](std::size_t c) {
    const vtkTypeInt64* cell = r.connectivity + 3 * (c / 3);
    const auto f = static_cast<std::uint32_t>(c / 3);
    if (cell[0] == cell[1] && cell[1] == cell[2] &&
        !std::binary_search(collapsed_.begin(), collapsed_.end(), f))
      return kInvalidIndex;
    return static_cast<std::uint32_t>(r.vertex_id[r.connectivity[c]]);
  });
  collapsed_ = {};
  // The uses of every point (a copying build leaves them to be counted here).
  std::fill(uses_.begin(), uses_.end(), 0);
  for (std::size_t c = 0; c < corners; ++c)
    if (corner_vertex_[c] != kInvalidIndex) ++uses_[static_cast<std::size_t>(r.connectivity[c])];
}

void ViewPolyData::prepare_updates() {
  if (corners_ && !lists_) link_cells();
}

void ViewPolyData::link(std::uint32_t c, std::uint32_t v) {
  corner_vertex_[c] = v;
  prev_[c] = kInvalidIndex;
  next_[c] = first_[v];
  if (first_[v] != kInvalidIndex) prev_[first_[v]] = c;
  first_[v] = c;
}

void ViewPolyData::unlink(std::uint32_t c) {
  const std::uint32_t v = corner_vertex_[c];
  if (v == kInvalidIndex) return;
  if (prev_[c] != kInvalidIndex)
    next_[prev_[c]] = next_[c];
  else
    first_[v] = next_[c];
  if (next_[c] != kInvalidIndex) prev_[next_[c]] = prev_[c];
  corner_vertex_[c] = next_[c] = prev_[c] = kInvalidIndex;
}

void ViewPolyData::update(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                          const std::vector<glm::vec3>* corner_normals, const PrimitiveChange& change) {
  prepare_updates();  // (the lists of the state before the step)
  const vtkIdType old_points = poly_->GetNumberOfPoints(), old_cells = poly_->GetNumberOfCells();
  bool reassigned = false;  // a point now draws another vertex or corner than before
  if (corners_) {
    reassigned = update_corner_points(mesh, positions, corner_normals, change);
  } else {
    const std::size_t slots = mesh.face_slots(), vertices = mesh.vertex_count();
    const std::size_t kept_faces = std::min(change.faces_before, slots);
    const std::size_t kept_vertices = std::min(change.vertices_before, vertices);
    resize(mesh);
    const Writer w(poly_, mesh, positions, corner_normals);
    for (FaceId f : change.faces)
      if (f.index < kept_faces) w.vertex_cell(f.index);
    for (std::size_t f = kept_faces; f < slots; ++f) w.vertex_cell(f);
    for (VertexId v : change.vertices)
      if (v.index < kept_vertices) w.vertex_point(v.index);
    for (std::size_t v = kept_vertices; v < vertices; ++v) w.vertex_point(v);
  }
  if (reassigned || poly_->GetNumberOfPoints() != old_points) poly_->GetPointData()->RemoveArray("colors");
  if (poly_->GetNumberOfCells() != old_cells) poly_->GetCellData()->RemoveArray("colors");
  // The cell map (cell types and places, built for picking) no longer fits a new cell count.
  if (poly_->GetNumberOfCells() != old_cells) poly_->DeleteCells();
  vertices_ = mesh.vertex_count();
  modified();
}

bool ViewPolyData::update_corner_points(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                                        const std::vector<glm::vec3>* corner_normals,
                                        const PrimitiveChange& change) {
  const std::size_t slots = mesh.face_slots(), vertices = mesh.vertex_count();
  const std::size_t kept_faces = std::min(change.faces_before, slots);
  const std::size_t kept_vertices = std::min(change.vertices_before, vertices);
  // 1. Corners of faces that are gone or rewritten, and of listed vertices, leave their points
  // (and the first ones their vertices' lists); the vertices they leave or join are regrouped.
  std::vector<std::uint32_t> dead, regroup;
  // Point 0 stays while no face is live (a deleted face's cell names it); unused, it is free
  // for the first new point again.
  if (uses_[0] == 0) dead.push_back(0);
  auto leave = [&](std::uint32_t c) {
    if (corner_vertex_[c] == kInvalidIndex) return;
    regroup.push_back(corner_vertex_[c]);
    release(c, dead);
    unlink(c);
  };
  for (std::size_t c = 3 * kept_faces; c < corner_vertex_.size(); ++c) leave(static_cast<std::uint32_t>(c));
  for (FaceId f : change.faces)
    if (f.index < kept_faces)
      for (std::uint32_t c = 3 * f.index; c < 3 * f.index + 3; ++c) leave(c);
  for (VertexId v : change.vertices)
    if (v.index < kept_vertices) {
      regroup.push_back(v.index);
      for (std::uint32_t c = first_[v.index]; c != kInvalidIndex; c = next_[c]) release(c, dead);
    }
  first_.resize(vertices, kInvalidIndex);
  next_.resize(3 * slots, kInvalidIndex);
  prev_.resize(3 * slots, kInvalidIndex);
  corner_vertex_.resize(3 * slots, kInvalidIndex);
  resize(mesh);
  // 2. Listed and new faces: live ones link their corners (without a point yet), deleted ones
  // draw nothing.
  vtkTypeInt64* conn = poly_->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  auto relink = [&](std::size_t f) {
    const bool live = !mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)));
    for (std::size_t c = 3 * f; c < 3 * f + 3; ++c) {
      conn[c] = live ? -1 : 0;
      if (!live) continue;
      const std::uint32_t v = mesh.faces()[f][static_cast<int>(c % 3)].index;
      link(static_cast<std::uint32_t>(c), v);
      regroup.push_back(v);
    }
  };
  for (FaceId f : change.faces)
    if (f.index < kept_faces) relink(f.index);
  for (std::size_t f = kept_faces; f < slots; ++f) relink(f);
  // 3. Regroup (room first for a new point per waiting corner), then close the gaps.
  std::sort(regroup.begin(), regroup.end());
  regroup.erase(std::unique(regroup.begin(), regroup.end()), regroup.end());
  std::size_t waiting = 0;
  for (std::uint32_t v : regroup)
    if (v < vertices)
      for (std::uint32_t c = first_[v]; c != kInvalidIndex; c = next_[c]) waiting += conn[c] < 0;
  const std::size_t points = uses_.size();
  set_point_count(points + waiting);
  Writer w(poly_, mesh, positions, corner_normals);
  bool wrote = false;
  for (std::uint32_t v : regroup)
    if (v < vertices) wrote |= assign_points(w, v, linked(v), dead);
  set_point_count(uses_.size());
  compact(dead);
  return wrote;
}

// A corner of vertex `v` keeps its point or, waiting (connectivity -1), takes one that draws
// alike: first the vertex's points in use, then new ones.
bool ViewPolyData::assign_points(const Writer& w, std::uint32_t v, const Corners& corners,
                                 std::vector<std::uint32_t>& dead) {
  vtkTypeInt64* conn = w.r.connectivity;
  bool wrote = false;
  Candidates seen;
  corners.any([&](std::uint32_t c) {
    if (conn[c] >= 0) {
      const auto p = static_cast<std::uint32_t>(conn[c]);
      if (point_corner_[p] == kInvalidIndex) point_corner_[p] = c;  // its corner left
      seen.add(p, point_corner_[p]);
    }
    return false;
  });
  corners.any([&](std::uint32_t c) {
    if (conn[c] >= 0) return false;
    std::uint32_t p = alike_point(w, seen, corners, c, conn);
    if (p == kInvalidIndex) {
      if (!dead.empty()) {
        p = dead.back();
        dead.pop_back();
      } else {
        p = static_cast<std::uint32_t>(uses_.size());
        uses_.push_back(0);
        point_corner_.push_back(kInvalidIndex);
      }
      w.point(p, v, c);
      point_corner_[p] = c;
      seen.add(p, c);
      wrote = true;
    }
    conn[c] = p;
    ++uses_[p];
    return false;
  });
  return wrote;
}

void ViewPolyData::release(std::uint32_t c, std::vector<std::uint32_t>& dead) {
  vtkTypeInt64* conn = poly_->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  if (conn[c] < 0) return;  // already left
  const auto p = static_cast<std::uint32_t>(conn[c]);
  conn[c] = -1;
  if (point_corner_[p] == c) point_corner_[p] = kInvalidIndex;
  if (--uses_[p] == 0) dead.push_back(p);
}

void ViewPolyData::compact(std::vector<std::uint32_t>& dead) {
  // From the highest: the last point is then in use (or the dead one itself). Its corners are
  // found through its vertex's list and follow it.
  std::sort(dead.begin(), dead.end(), std::greater<>());
  vtkPointData* pd = poly_->GetPointData();
  vtkDataArray* points = poly_->GetPoints()->GetData();
  vtkTypeInt64* conn = poly_->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  std::size_t count = uses_.size();
  for (std::uint32_t p : dead) {
    if (count == 1) break;  // a deleted face's cell needs point 0
    const auto last = static_cast<std::uint32_t>(--count);
    if (p != last) {
      points->SetTuple(p, last, points);
      // Every point array moves with its point, "colors" included: the moved point keeps its
      // own colour, so none is shown on another point (and `update` drops the colours anyway,
      // as the count shrinks).
      for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
        if (vtkAbstractArray* a = pd->GetAbstractArray(i)) a->SetTuple(p, last, a);
      const auto v = static_cast<std::uint32_t>(pd->GetArray("vertex_id")->GetTuple1(p));
      for (std::uint32_t c = first_[v]; c != kInvalidIndex; c = next_[c])
        if (conn[c] == last) conn[c] = p;
      uses_[p] = uses_[last];
      point_corner_[p] = point_corner_[last];
    }
  }
  uses_.resize(count);
  point_corner_.resize(count);
  dead.clear();
  set_point_count(count);
  if (uses_[0] == 0) clear_point(raw(poly_), 0);
}

void ViewPolyData::set_positions(const std::vector<glm::vec3>& positions,
                                 const std::vector<glm::vec3>* corner_normals) {
  const Raw r = raw(poly_);
  const auto n = static_cast<std::size_t>(poly_->GetNumberOfPoints());
  const bool with_normals = r.normals && corner_normals && !corner_normals->empty();
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const auto v = static_cast<std::size_t>(r.vertex_id[i]);
      // (a point no corner uses keeps its normal)
      const std::uint32_t c = corners_ ? point_corner_[i] : kInvalidIndex;
      const glm::vec3* normal = with_normals && c != kInvalidIndex ? &(*corner_normals)[c] : nullptr;
      if (v < positions.size()) write_point(r, i, positions[v], normal);
    }
  });
  modified();
}

void ViewPolyData::modified() {
  vtkPointData* pd = poly_->GetPointData();
  poly_->GetPoints()->Modified();
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    if (vtkAbstractArray* a = pd->GetAbstractArray(i)) a->Modified();
  poly_->GetCellData()->GetAbstractArray("face_id")->Modified();
  poly_->GetPolys()->Modified();
  poly_->Modified();
}

}  // namespace deepcut
