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

#include "deepcut/core/parallel.h"

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

std::uint32_t safe_vertex(const SurfaceMesh& mesh, VertexId v) {
  return v.index < mesh.vertex_count() ? v.index : 0u;
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

  Writer(vtkPolyData* poly, const SurfaceMesh& m, const std::vector<glm::vec3>& p, const std::vector<glm::vec3>* n)
      : r(raw(poly)), mesh(m), positions(p) {
    if (const auto* a = m.corner_attrs().find<glm::vec2>(attr::kUv0)) uv = a->data().data();
    if (n && !n->empty())
      normals = n->data();
    else if (const auto* a = m.corner_attrs().find<glm::vec3>(attr::kNormal))
      normals = a->data().data();
  }

  void corner(std::size_t c) const {
    const FaceId f(static_cast<std::uint32_t>(c / 3));
    const bool deleted = mesh.is_deleted(f);
    const std::uint32_t v = safe_vertex(mesh, mesh.face(f)[static_cast<int>(c % 3)]);
    const glm::vec3& p = positions[v];
    std::copy(&p.x, &p.x + 3, r.points + 3 * c);
    r.vertex_id[c] = v;
    r.connectivity[c] = static_cast<vtkTypeInt64>(deleted ? 3 * f.index : c);
    if (r.uv && uv) {
      r.uv[2 * c] = uv[c].x;
      r.uv[2 * c + 1] = uv[c].y;
    }
    if (r.normals && normals) {
      const glm::vec3 n = deleted ? glm::vec3(0.0f) : normals[c];
      std::copy(&n.x, &n.x + 3, r.normals + 3 * c);
    }
  }

  void vertex_cell(std::size_t f) const {
    const FaceId face(static_cast<std::uint32_t>(f));
    const Triangle& t = mesh.face(face);
    const bool deleted = mesh.is_deleted(face);
    for (int k = 0; k < 3; ++k)
      r.connectivity[3 * f + static_cast<std::size_t>(k)] = safe_vertex(mesh, deleted ? t[0] : t[k]);
  }

  void vertex_point(std::size_t v) const {
    std::copy(&positions[v].x, &positions[v].x + 3, r.points + 3 * v);
    r.vertex_id[v] = static_cast<vtkIdType>(v);
  }
};

namespace {

}  // namespace

ViewPolyData::ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                           const std::vector<glm::vec3>* corner_normals) {
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

  resize(mesh);
  const std::size_t slots = mesh.face_slots();
  if (corners_) {
    first_.assign(mesh.vertex_count(), kInvalidIndex);
    next_.assign(3 * slots, kInvalidIndex);
    prev_.assign(3 * slots, kInvalidIndex);
    corner_vertex_.assign(3 * slots, kInvalidIndex);
    link_all(mesh);
    const Writer w(poly_, mesh, positions, corner_normals);
    parallel_for(3 * slots, kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t c = b; c < e; ++c) w.corner(c);
    });
  } else {
    const Writer w(poly_, mesh, positions, corner_normals);
    parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f < e; ++f) w.vertex_cell(f);
    });
    parallel_for(mesh.vertex_count(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v < e; ++v) w.vertex_point(v);
    });
  }
  modified();
}

void ViewPolyData::resize(const SurfaceMesh& mesh) {
  const std::size_t slots = mesh.face_slots();
  const std::size_t points = corners_ ? 3 * slots : mesh.vertex_count();
  vtkPointData* pd = poly_->GetPointData();
  set_count(vtkFloatArray::SafeDownCast(poly_->GetPoints()->GetData()), points);
  set_count(named<vtkIdTypeArray>(pd, "vertex_id"), points);
  if (auto* a = named<vtkFloatArray>(pd, "uv0")) set_count(a, points);
  if (auto* a = vtkFloatArray::SafeDownCast(pd->GetNormals())) set_count(a, points);
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

void ViewPolyData::link_all(const SurfaceMesh& mesh) {
  // A list crosses any chunk of corners, so the work is cut by vertices: each range scans every
  // corner (from the last: `link` pushes to the front) and links those of its own vertices. The
  // lists are the same for any number of ranges; all writes of a range are to its vertices'
  // slots and their corners.
  const std::size_t corners = 3 * mesh.face_slots(), vertices = mesh.vertex_count();
  const std::size_t ranges = std::min<std::size_t>(thread_count(), 8);
  parallel_for(ranges, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t r = b; r < e; ++r) {
      const std::size_t lo = vertices * r / ranges, hi = vertices * (r + 1) / ranges;
      for (std::size_t c = corners; c-- > 0;) {
        const std::uint32_t v = mesh.faces()[c / 3][static_cast<int>(c % 3)].index;
        if (v >= lo && v < hi && !mesh.is_deleted(FaceId(static_cast<std::uint32_t>(c / 3))))
          link(static_cast<std::uint32_t>(c), v);
      }
    }
  });
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
  const std::size_t slots = mesh.face_slots(), vertices = mesh.vertex_count();
  const std::size_t kept_faces = std::min(change.faces_before, slots);
  const std::size_t kept_vertices = std::min(change.vertices_before, vertices);
  const vtkIdType old_points = poly_->GetNumberOfPoints(), old_cells = poly_->GetNumberOfCells();
  if (corners_) {
    // Corners of faces that are gone or rewritten leave their vertices' lists first.
    for (std::size_t c = 3 * kept_faces; c < corner_vertex_.size(); ++c) unlink(static_cast<std::uint32_t>(c));
    for (FaceId f : change.faces)
      if (f.index < kept_faces)
        for (std::uint32_t c = 3 * f.index; c < 3 * f.index + 3; ++c) unlink(c);
    first_.resize(vertices, kInvalidIndex);
    next_.resize(3 * slots, kInvalidIndex);
    prev_.resize(3 * slots, kInvalidIndex);
    corner_vertex_.resize(3 * slots, kInvalidIndex);
  }
  resize(mesh);
  const Writer w(poly_, mesh, positions, corner_normals);
  if (corners_) {
    auto rewrite_face = [&](std::size_t f) {
      const bool live = !mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)));
      for (std::size_t c = 3 * f; c < 3 * f + 3; ++c) {
        if (live) link(static_cast<std::uint32_t>(c), mesh.faces()[f][static_cast<int>(c % 3)].index);
        w.corner(c);
      }
    };
    for (FaceId f : change.faces)
      if (f.index < kept_faces) rewrite_face(f.index);
    for (std::size_t f = kept_faces; f < slots; ++f) rewrite_face(f);
    // A listed vertex moved (or its linear map, hence its corners' normals, changed).
    for (VertexId v : change.vertices)
      if (v.index < kept_vertices)
        for (std::uint32_t c = first_[v.index]; c != kInvalidIndex; c = next_[c])
          w.corner(c);
  } else {
    for (FaceId f : change.faces)
      if (f.index < kept_faces) w.vertex_cell(f.index);
    for (std::size_t f = kept_faces; f < slots; ++f) w.vertex_cell(f);
    for (VertexId v : change.vertices)
      if (v.index < kept_vertices) w.vertex_point(v.index);
    for (std::size_t v = kept_vertices; v < vertices; ++v) w.vertex_point(v);
  }
  if (poly_->GetNumberOfPoints() != old_points || poly_->GetNumberOfCells() != old_cells) {
    poly_->GetPointData()->RemoveArray("colors");
    poly_->GetCellData()->RemoveArray("colors");
  }
  // The cell map (cell types and places, built for picking) no longer fits a new cell count.
  if (poly_->GetNumberOfCells() != old_cells) poly_->DeleteCells();
  modified();
}

void ViewPolyData::set_positions(const std::vector<glm::vec3>& positions,
                                 const std::vector<glm::vec3>* corner_normals) {
  const Raw r = raw(poly_);
  const auto n = static_cast<std::size_t>(poly_->GetNumberOfPoints());
  const bool with_normals = r.normals && corner_normals && !corner_normals->empty();
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const glm::vec3& p = positions[static_cast<std::size_t>(r.vertex_id[i])];
      std::copy(&p.x, &p.x + 3, r.points + 3 * i);
      // Corners of deleted faces keep a zero normal (as written).
      const bool drawn = !corners_ || corner_vertex_[i] != kInvalidIndex;
      if (with_normals && drawn) std::copy(&(*corner_normals)[i].x, &(*corner_normals)[i].x + 3, r.normals + 3 * i);
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
