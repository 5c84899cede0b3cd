// SPDX-License-Identifier: MIT
// ViewPolyData's arrays, its full build (corners grouped by vertex), its corner lists, its
// updates by step and its new poses. The copying build is in view_poly_data_copy.cpp.
#include "deepcut/widgets/view_poly_data.h"

#include <vtkNew.h>

#include <algorithm>
#include <cassert>
#include <cstring>
#include <functional>

#include "corner_groups.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_corner_normal.h"
#include "view_poly_data_writer.h"

namespace deepcut {

using view_data::clear_point;
using view_data::kGrain;
using view_data::named;
using view_data::raw;
using view_data::Raw;
using view_data::write_point;

namespace {

// `spare` (an array of a spare data, or null) when it is an Array with `components` components,
// marked modified (ranges cached for its values before are stale); else a new one named `name`.
template <class Array>
vtkSmartPointer<Array> reused_or_new(vtkAbstractArray* spare, const char* name, int components) {
  if (auto* a = Array::SafeDownCast(spare); a && a->GetNumberOfComponents() == components) {
    a->Modified();
    return a;
  }
  auto a = vtkSmartPointer<Array>::New();
  if (name) a->SetName(name);
  a->SetNumberOfComponents(components);
  return a;
}

// Makes `a` hold exactly `room` tuples, the values below kept. VTK's Resize(k), for k past what
// the array holds, grows it to what it held plus k (a Resize(k) below that shrinks it to k), so a
// growth asks for the difference, at least what it held and one: to exactly `room` where that is
// over twice what it held, else to twice that and squeezed back to `room` (in place).
template <class Array>
void set_room(Array* a, std::size_t room) {
  const vtkIdType components = a->GetNumberOfComponents();
  const auto want = static_cast<vtkIdType>(room);
  const vtkIdType held = a->GetSize() / components;
  if (want > held) a->Resize(std::max(want - held, held + 1));
  if (a->GetSize() / components != want) a->Resize(want);
}

// Sets `n` tuples, keeping the values below, with room to grow by a step (view_data::room_size)
// and at most n + 2 x (n / 8 + 64) tuples (too_roomy: memory taken from a spare, or left as the
// data shrank, goes back down to room_size(n)).
template <class Array>
void set_count(Array* a, std::size_t n) {
  if (n == 0) {  // (VTK frees the block at 0 tuples: room set first would be a wasted reallocation)
    a->SetNumberOfTuples(0);
    return;
  }
  const auto held = static_cast<std::size_t>(a->GetSize() / a->GetNumberOfComponents());
  if (n > held || view_data::too_roomy(held, n)) set_room(a, view_data::room_size(n));
  a->SetNumberOfTuples(static_cast<vtkIdType>(n));
}

}  // namespace

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

ViewPolyData::Corners ViewPolyData::linked(std::uint32_t v) const { return {next_.data(), first_[v]}; }

namespace {

// The point (connectivity `conn` >= 0) of a corner among `corners` other than `c` that draws like
// `c`, else kInvalidIndex: the scan of every corner of a vertex, for one with more points than
// `Candidates` keeps (alike_point's second half, without its first).
template <class Writer, class Corners>
std::uint32_t scan_alike(const Writer& w, const Corners& corners, std::uint32_t c, const vtkTypeInt64* conn) {
  std::uint32_t p = kInvalidIndex;
  corners.any([&](std::uint32_t d) {
    if (d == c || conn[d] < 0 || !w.alike(d, c)) return false;
    p = static_cast<std::uint32_t>(conn[d]);
    return true;
  });
  return p;
}

}  // namespace

std::uint32_t ViewPolyData::alike_point(const Writer& w, const Candidates& seen, const Corners& corners,
                                        std::uint32_t c, const vtkTypeInt64* conn) const {
  const std::uint32_t p = seen.find(w, c);
  if (p != kInvalidIndex || !seen.full) return p;
  return scan_alike(w, corners, c, conn);
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
                           const CornerNormalPoser& posed)
    : ViewPolyData(mesh, positions, static_cast<const std::vector<glm::vec3>*>(nullptr)) {
  // Built with the mesh's own normals (grouped alike), then each point's normal posed from the
  // corner it draws like.
  const view_data::Raw r = view_data::raw(poly_);
  if (!corners_ || !r.normals || !posed.has_normals()) return;
  parallel_for(point_corner_.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const std::uint32_t c = point_corner_[p];
      if (c == kInvalidIndex) continue;
      const glm::vec3 n = posed(static_cast<std::uint32_t>(r.vertex_id[p]), c);
      float* const to = r.normals + 3 * p;
      to[0] = n.x, to[1] = n.y, to[2] = n.z;
    }
  });
  modified();
}

ViewPolyData::ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                           const std::vector<glm::vec3>* corner_normals, const ViewPolyData& source,
                           const PrimitiveOrigin& origin, ViewPolyData* spare, CopyScratch* scratch) {
  if (!copy_fits(mesh, source, origin)) {
    *this = ViewPolyData(mesh, positions, corner_normals);
    return;
  }
  make_arrays(mesh, spare && spare != &source && can_take(*spare, mesh.face_slots()) ? spare : nullptr);
  resize(mesh);
  vertices_ = mesh.vertex_count();
  CopyScratch own;  // (without `scratch`)
  copy_corner_points(Writer(poly_, mesh, positions, corner_normals), source, origin,
                     scratch ? *scratch : own);
  copied_ = true;
  modified();
}

bool ViewPolyData::draws_corners(const SurfaceMesh& mesh) {
  const auto& ca = mesh.corner_attrs();
  return ca.find<glm::vec2>(attr::kUv0) || ca.find<glm::vec3>(attr::kNormal);
}

void ViewPolyData::make_arrays(const SurfaceMesh& mesh, ViewPolyData* spare) {
  const auto& ca = mesh.corner_attrs();
  corners_ = draws_corners(mesh);
  const bool uv = corners_ && ca.find<glm::vec2>(attr::kUv0);
  const bool normal = corners_ && ca.find<glm::vec3>(attr::kNormal);
  vtkPolyData* const from = spare ? spare->poly_.Get() : nullptr;
  vtkPointData* const from_pd = from ? from->GetPointData() : nullptr;
  vtkCellArray* const from_cells = from ? from->GetPolys() : nullptr;
  poly_ = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetData(reused_or_new<vtkFloatArray>(from ? from->GetPoints()->GetData() : nullptr, nullptr, 3));
  poly_->SetPoints(points);
  vtkPointData* pd = poly_->GetPointData();
  pd->AddArray(reused_or_new<vtkIdTypeArray>(from_pd ? named<vtkIdTypeArray>(from_pd, "vertex_id") : nullptr,
                                             "vertex_id", 1));
  if (uv)
    pd->SetTCoords(
        reused_or_new<vtkFloatArray>(from_pd ? named<vtkFloatArray>(from_pd, "uv0") : nullptr, "uv0", 2));
  if (normal)
    pd->SetNormals(reused_or_new<vtkFloatArray>(from_pd ? from_pd->GetNormals() : nullptr, "normal", 3));
  auto face_ids = reused_or_new<vtkIdTypeArray>(
      from ? named<vtkIdTypeArray>(from->GetCellData(), "face_id") : nullptr, "face_id", 1);
  poly_->GetCellData()->AddArray(face_ids);
  vtkNew<vtkCellArray> polys;
  auto offsets =
      reused_or_new<vtkTypeInt64Array>(from_cells ? from_cells->GetOffsetsArray64() : nullptr, nullptr, 1);
  polys->SetData(offsets, reused_or_new<vtkTypeInt64Array>(
                              from_cells ? from_cells->GetConnectivityArray64() : nullptr, nullptr, 1));
  poly_->SetPolys(polys);
  if (!spare) return;
  // A data's offsets and face ids are the identity (resize writes only those past its cells).
  const vtkIdType cells = face_ids->GetNumberOfTuples();
  assert(cells == 0 || (offsets->GetValue(cells) == 3 * cells && face_ids->GetValue(cells - 1) == cells - 1));
  (void)cells;
  // The per-point lists are sized by the copy (too roomy ones given back); the corner lists go
  // with the spare: a copy is drawn without them, perhaps for good (the studio prepares no
  // copied piece), and the spare's were sized for its own corners, maybe many more.
  uses_.swap(spare->uses_);
  point_corner_.swap(spare->point_corner_);
  spare->poly_ = nullptr;
}

namespace {

// Corner `c`'s attributes that decide how it draws, as 64-bit words compared bit for bit (as
// Writer::alike compares them): `N` three-float arrays (the normals, then the other normal
// sources), two words each (the third float in the low half of the second word, the rest zero),
// then, with `UV`, the texture coordinates.
template <int N, bool UV>
struct CornerWords {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::vec2) == sizeof(std::uint64_t));
  static constexpr int kWords = 2 * N + (UV ? 1 : 0);
  const glm::vec3* vec3[N > 0 ? N : 1] = {};
  const glm::vec2* uv = nullptr;
  void load(std::uint32_t c, std::uint64_t* w) const {
    for (int i = 0; i < N; ++i) {
      const glm::vec3& x = vec3[i][c];
      std::uint32_t z;
      std::memcpy(&w[2 * i], &x, sizeof(std::uint64_t));
      std::memcpy(&z, &x.z, sizeof z);
      w[2 * i + 1] = z;
    }
    if constexpr (UV) std::memcpy(&w[2 * N], &uv[c], sizeof(std::uint64_t));
  }
  static bool same(const std::uint64_t* a, const std::uint64_t* b) {
    std::uint64_t diff = 0;
    for (int i = 0; i < kWords; ++i) diff |= a[i] ^ b[i];
    return diff == 0;
  }
};

// Numbers the points of vertices [b, e) from 0 each, into `conn` (a corner's number among its
// vertex's points: the points in the order of their first corners, the vertex's corners
// ascending), and each vertex's point count into `counts[v + 1]`. A corner's words are read
// once and compared with those of the first few points' first corners (kept), else, for a
// vertex with more points, with every corner before it: the same numbers as a scan of every
// corner before, as drawing alike is bitwise equality.
template <class Key>
void number_points(const Key& key, const CornerGroups& groups, std::size_t b, std::size_t e,
                   vtkTypeInt64* conn, std::uint32_t* counts) {
  constexpr std::uint32_t kKept = 32;  // how many is speed only: the numbers do not depend on it
  constexpr int kWords = Key::kWords > 0 ? Key::kWords : 1;
  const std::uint32_t* grouped = groups.corner.data();
  const std::uint32_t* offset = groups.offset.data();
  std::uint64_t kept[kKept][kWords];
  for (std::size_t v = b; v < e; ++v) {
    const std::uint32_t* const begin = grouped + offset[v];
    const std::uint32_t* const end = grouped + offset[v + 1];
    std::uint32_t count = 0;
    if (begin != end) {  // the first corner: point 0
      key.load(*begin, kept[0]);
      conn[*begin] = 0;
      count = 1;
    }
    for (const std::uint32_t* at = begin + (begin != end); at < end; ++at) {
      const std::uint32_t c = *at;
      std::uint64_t w[kWords];
      key.load(c, w);
      if (key.same(kept[0], w)) {  // (most corners: a vertex drawn one way)
        conn[c] = 0;
        continue;
      }
      const std::uint32_t known = std::min(count, kKept);
      std::uint32_t p = 1;
      while (p < known && !key.same(kept[p], w)) ++p;
      if (p == known) {
        p = kInvalidIndex;
        if (count > kKept)
          for (const std::uint32_t* d = begin; d != at; ++d) {
            std::uint64_t x[kWords];
            key.load(*d, x);
            if (key.same(x, w)) {
              p = static_cast<std::uint32_t>(conn[*d]);
              break;
            }
          }
        if (p == kInvalidIndex) {
          if (count < kKept) std::copy(w, w + kWords, kept[count]);
          p = count++;
        }
      }
      conn[c] = p;
    }
    counts[v + 1] = count;
  }
}

// Writer::alike behind the interface of CornerWords (a corner's "words" are the corner itself):
// for more normal sources than the words cover.
template <class Writer>
struct AlikeKey {
  static constexpr int kWords = 1;
  const Writer& w;
  void load(std::uint32_t c, std::uint64_t* x) const { x[0] = c; }
  bool same(const std::uint64_t* a, const std::uint64_t* b) const { return w.alike(a[0], b[0]); }
};

// Numbers each live corner's point among its vertex's points (into `writer`'s connectivity:
// number_points) and each vertex's point count into `counts[v + 1]`; a deleted face's cell is
// (0, 0, 0). The corners are compared through the words of the arrays the writer draws with, or
// Writer::alike where there are more arrays than the words cover.
template <class Writer>
void number_corner_points(const Writer& writer, const CornerGroups& groups, std::uint32_t* counts) {
  const SurfaceMesh& mesh = writer.mesh;
  vtkTypeInt64* conn = writer.r.connectivity;
  if (mesh.face_count() != mesh.face_slots())
    parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f < e; ++f)
        if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))))
          std::fill(conn + 3 * f, conn + 3 * f + 3, 0);
    });
  auto number = [&](const auto& key) {
    parallel_for(groups.offset.size() - 1, kGrain,
                 [&](std::size_t b, std::size_t e) { number_points(key, groups, b, e, conn, counts); });
  };
  std::vector<const glm::vec3*> vec3;  // the three-float arrays that decide how a corner draws
  if (writer.normals) vec3.push_back(writer.normals);
  for (const glm::vec3* a : writer.normal_sources) vec3.push_back(a);
  auto with = [&](auto words) {  // the one CornerWords whose words fit (2N + UV differs for each)
    using Words = decltype(words);
    if (2 * vec3.size() + (writer.uv ? 1 : 0) != Words::kWords) return false;
    std::copy(vec3.begin(), vec3.end(), words.vec3);
    words.uv = writer.uv;
    number(words);
    return true;
  };
  if (!(with(CornerWords<0, true>{}) || with(CornerWords<1, false>{}) || with(CornerWords<1, true>{}) ||
        with(CornerWords<2, false>{}) || with(CornerWords<2, true>{}) || with(CornerWords<3, false>{}) ||
        with(CornerWords<3, true>{}) || with(CornerWords<4, false>{}) || with(CornerWords<4, true>{})))
    number(AlikeKey<Writer>{writer});  // no arrays, or more than the words cover
}

}  // namespace

void ViewPolyData::build_corner_points(const Writer& writer, const CornerGroups& groups) {
  const std::size_t vertices = groups.offset.size() - 1;
  // Two passes over each vertex's corners: the first numbers its points from 0 (into the corners'
  // connectivity), the second adds the vertex's first point and writes the points.
  vtkTypeInt64* conn = writer.r.connectivity;
  const std::uint32_t* grouped = groups.corner.data();
  std::vector<std::uint32_t> first_point(vertices + 1, 0);
  number_corner_points(writer, groups, first_point.data());
  for (std::size_t v = 0; v < vertices; ++v) first_point[v + 1] += first_point[v];
  const std::size_t points = first_point[vertices];
  set_point_count(std::max<std::size_t>(points, 1));  // a deleted face's cell needs point 0
  view_data::refill(uses_, std::max<std::size_t>(points, 1), 0u);
  view_data::refill(point_corner_, uses_.size(), kInvalidIndex);
  Writer w = writer;
  w.refresh(poly_);
  if (points == 0) clear_point(w.r, 0);
  std::uint32_t* const uses = uses_.data();
  std::uint32_t* const point_corner = point_corner_.data();
  const std::uint32_t* const offset = groups.offset.data();
  parallel_for(vertices, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const std::uint32_t first = first_point[v];
      if (first_point[v + 1] == first + 1) {  // drawn one way: every corner's point is the first
        const std::uint32_t* const begin = grouped + offset[v];
        const std::uint32_t* const end = grouped + offset[v + 1];
        for (const std::uint32_t* at = begin; at != end; ++at) conn[*at] = first;
        uses[first] = static_cast<std::uint32_t>(end - begin);
        w.point(first, static_cast<std::uint32_t>(v), *begin);
        point_corner[first] = *begin;
        continue;
      }
      std::uint32_t written = 0;
      for (std::uint32_t i = offset[v], end = offset[v + 1]; i < end; ++i) {
        const std::uint32_t c = grouped[i];
        const auto local = static_cast<std::uint32_t>(conn[c]);
        const std::uint32_t p = first + local;
        conn[c] = p;
        ++uses[p];
        if (local == written) {
          w.point(p, static_cast<std::uint32_t>(v), c);
          point_corner[p] = c;
          ++written;
        }
      }
    }
  });
}

void ViewPolyData::set_point_count(std::size_t n) {
  if (corners_) {  // (assign_points appends to the per-point lists, up to the count set here)
    view_data::grow(uses_, n);
    view_data::grow(point_corner_, n);
  }
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
  view_data::refill(first_, vertices, kInvalidIndex);
  view_data::refill(next_, corners, kInvalidIndex);
  view_data::refill(prev_, corners, kInvalidIndex);
  view_data::refill(corner_vertex_, corners, kInvalidIndex);
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
  size_lists(vertices, 3 * slots);
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
  set_point_count(uses_.size() + waiting_corners(regroup, vertices));
  Writer w(poly_, mesh, positions, corner_normals);
  bool wrote = false;
  for (std::uint32_t v : regroup)
    if (v < vertices) wrote |= assign_points(w, v, linked(v), dead);
  set_point_count(uses_.size());
  compact(dead);
  return wrote;
}

void ViewPolyData::size_lists(std::size_t vertices, std::size_t corners) {
  for (auto* list : {&first_, &next_, &prev_, &corner_vertex_}) {
    const std::size_t n = list == &first_ ? vertices : corners;
    view_data::grow(*list, n);
    list->resize(n, kInvalidIndex);
    view_data::fit(*list);  // (fewer slots: an undo of a drill; copies only past too_roomy)
  }
}

std::size_t ViewPolyData::waiting_corners(const std::vector<std::uint32_t>& vertices,
                                          std::size_t count) const {
  const vtkTypeInt64* conn = poly_->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  std::size_t waiting = 0;
  for (std::uint32_t v : vertices)
    if (v < count)
      for (std::uint32_t c = first_[v]; c != kInvalidIndex; c = next_[c]) waiting += conn[c] < 0;
  return waiting;
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
  view_data::fit(uses_);
  view_data::fit(point_corner_);
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

ViewPolyData::Bytes ViewPolyData::bytes() const {
  Bytes b;
  auto add = [&](vtkAbstractArray* a) {
    if (!a) return;
    const auto element = static_cast<std::size_t>(a->GetDataTypeSize());
    b.used += static_cast<std::size_t>(a->GetNumberOfValues()) * element;
    b.held += static_cast<std::size_t>(a->GetSize()) * element;
  };
  if (poly_) {
    add(poly_->GetPoints()->GetData());
    for (vtkDataSetAttributes* data : {static_cast<vtkDataSetAttributes*>(poly_->GetPointData()),
                                       static_cast<vtkDataSetAttributes*>(poly_->GetCellData())})
      for (int i = 0; i < data->GetNumberOfArrays(); ++i) add(data->GetAbstractArray(i));
    add(poly_->GetPolys()->GetOffsetsArray());
    add(poly_->GetPolys()->GetConnectivityArray());
  }
  for (const auto* v : {&uses_, &point_corner_, &collapsed_}) {
    b.used += v->size() * sizeof(std::uint32_t);
    b.held += v->capacity() * sizeof(std::uint32_t);
  }
  for (const auto* v : {&first_, &next_, &prev_, &corner_vertex_}) {
    b.used += lists_ ? v->size() * sizeof(std::uint32_t) : 0;  // (unbuilt, they draw nothing)
    b.lists += v->capacity() * sizeof(std::uint32_t);
  }
  b.held += b.lists;
  return b;
}

std::vector<const void*> ViewPolyData::blocks() const {
  std::vector<const void*> out;
  if (poly_) {
    out.push_back(poly_->GetPoints()->GetData()->GetVoidPointer(0));
    for (vtkDataSetAttributes* data : {static_cast<vtkDataSetAttributes*>(poly_->GetPointData()),
                                       static_cast<vtkDataSetAttributes*>(poly_->GetCellData())})
      for (int i = 0; i < data->GetNumberOfArrays(); ++i)
        out.push_back(data->GetAbstractArray(i)->GetVoidPointer(0));
    out.push_back(poly_->GetPolys()->GetOffsetsArray()->GetVoidPointer(0));
    out.push_back(poly_->GetPolys()->GetConnectivityArray()->GetVoidPointer(0));
  }
  for (const auto* v : {&uses_, &point_corner_, &collapsed_, &first_, &next_, &prev_, &corner_vertex_})
    out.push_back(v->data());
  return out;
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
