// SPDX-License-Identifier: MIT
#include "surface_mapper.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkInformation.h>
#include <vtkInformationDoubleVectorKey.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLIndexBufferObject.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtk_glew.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "deepcut/core/parallel.h"

namespace deepcut::studio {

vtkStandardNewMacro(SurfaceMapper);

namespace {

// The cells' bounds kept with a poly data, then the modification time they were kept at.
vtkInformationDoubleVectorKey* kept_cells_bounds() {
  static vtkInformationDoubleVectorKey* const key =
      new vtkInformationDoubleVectorKey("DEEPCUT_KEPT_CELLS_BOUNDS", "SurfaceMapper", 7);
  return key;
}

// Connectivity ids narrowed to index buffer entries, over the pool.
template <class Id>
void narrow(const Id* ids, std::size_t n, unsigned int* out) {
  parallel_for(n, std::size_t{1} << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) out[i] = static_cast<unsigned int>(ids[i]);
  });
}

// Whether every cell has three points (the connectivity's length alone does not say it).
template <class Offset>
bool uniform_triangles(const Offset* offsets, std::size_t cells) {
  std::atomic<bool> other{false};
  parallel_for(cells, std::size_t{1} << 16, [&](std::size_t b, std::size_t e) {
    bool bad = false;
    for (std::size_t c = b; c < e; ++c) bad |= offsets[c + 1] - offsets[c] != 3;
    if (bad) other.store(true, std::memory_order_relaxed);
  });
  return !other.load();
}

bool every_cell_a_triangle(vtkCellArray* polys) {
  const auto cells = static_cast<std::size_t>(polys->GetNumberOfCells());
  if (polys->IsStorage64Bit()) return uniform_triangles(polys->GetOffsetsArray64()->GetPointer(0), cells);
  return uniform_triangles(polys->GetOffsetsArray32()->GetPointer(0), cells);
}

void narrow_connectivity(vtkCellArray* polys, std::size_t n, unsigned int* out) {
  if (polys->IsStorage64Bit())
    narrow(polys->GetConnectivityArray64()->GetPointer(0), n, out);
  else
    narrow(polys->GetConnectivityArray32()->GetPointer(0), n, out);
}

// `ibo` made (Upload creates and binds it), given room for `n` indices and mapped for writing,
// so that the connectivity is narrowed straight into the memory the draw reads: no array of its
// own to fault in and fill, then copy. Null when the driver does not map it.
unsigned int* mapped_for_write(vtkOpenGLIndexBufferObject* ibo, std::size_t n) {
  const unsigned int none = 0;
  if (!ibo->Upload(&none, 1, vtkOpenGLIndexBufferObject::ElementArrayBuffer)) return nullptr;
  const auto bytes = static_cast<GLsizeiptr>(n * sizeof(unsigned int));
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, bytes, nullptr, GL_STATIC_DRAW);
  return static_cast<unsigned int*>(
      glMapBufferRange(GL_ELEMENT_ARRAY_BUFFER, 0, bytes, GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT));
}

// The triangle buffer made from the connectivity of `polys` (`n` ids): written in place when
// `map` and the buffer maps (and unmaps intact), else narrowed into an array and uploaded.
// @returns whether it was written in place.
bool upload_triangles(vtkOpenGLIndexBufferObject* ibo, vtkCellArray* polys, std::size_t n, bool map) {
  if (unsigned int* mapped = map ? mapped_for_write(ibo, n) : nullptr) {
    narrow_connectivity(polys, n, mapped);
    if (glUnmapBuffer(GL_ELEMENT_ARRAY_BUFFER) == GL_TRUE) return true;
  }
  std::unique_ptr<unsigned int[]> indices(new unsigned int[n]);  // every entry written below
  narrow_connectivity(polys, n, indices.get());
  ibo->Upload(indices.get(), n, vtkOpenGLIndexBufferObject::ElementArrayBuffer);
  return false;
}

}  // namespace

bool SurfaceMapper::triangles_only(vtkRenderer* ren, vtkActor* act, vtkPolyData* poly) {
  vtkProperty* prop = act->GetProperty();
  vtkCellArray* polys = poly->GetPolys();
  // No colour or normal read per cell (their buffers are indexed by the triangles VTK keeps),
  // nothing drawn but filled triangles.
  return prop->GetRepresentation() == VTK_SURFACE && !prop->GetEdgeVisibility() &&
         !prop->GetVertexVisibility() && !ren->GetSelector() && !GetScalarVisibility() &&
         !poly->GetCellData()->GetNormals() &&
         !poly->GetPointData()->GetAttribute(vtkDataSetAttributes::EDGEFLAG) &&
         poly->GetVerts()->GetNumberOfCells() == 0 && poly->GetLines()->GetNumberOfCells() == 0 &&
         poly->GetStrips()->GetNumberOfCells() == 0 && polys->GetNumberOfCells() > 0 &&
         polys->GetNumberOfConnectivityIds() == 3 * polys->GetNumberOfCells();
}

void SurfaceMapper::BuildIBO(vtkRenderer* ren, vtkActor* act, vtkPolyData* poly) {
  if (!triangles_only(ren, act, poly)) {
    built_.clear();
    Superclass::BuildIBO(ren, act, poly);
    return;
  }
  vtkCellArray* polys = poly->GetPolys();
  // The cell array and its two arrays (a writer may mark either modified).
  const std::string key = std::to_string(reinterpret_cast<std::uintptr_t>(polys)) + ':' +
                          std::to_string(polys->GetMTime()) + ':' +
                          std::to_string(polys->GetConnectivityArray()->GetMTime()) + ':' +
                          std::to_string(polys->GetOffsetsArray()->GetMTime());
  if (key == built_) return;  // new positions only (a pose): the triangles are those uploaded
  if (!every_cell_a_triangle(polys)) {  // e.g. a quad and a two-point cell: VTK's build
    built_.clear();
    Superclass::BuildIBO(ren, act, poly);
    return;
  }
  const auto n = static_cast<std::size_t>(polys->GetNumberOfConnectivityIds());
  vtkOpenGLIndexBufferObject* tris = Primitives[PrimitiveTris].IBO;
  last_mapped_ = upload_triangles(tris, polys, n, map_uploads_);
  tris->IndexCount = n;
  for (int p = PrimitiveStart; p < PrimitiveEnd; ++p)
    if (p != PrimitiveTris) Primitives[p].IBO->IndexCount = 0;
  IBOBuildState.Clear();  // VTK's own build, when it is next asked, starts again from scratch
  built_ = key;
}

void SurfaceMapper::keep_cells_bounds(vtkPolyData* poly, const double bounds[6]) {
  vtkTimeStamp now;
  now.Modified();  // later than every change to `poly` so far
  double kept[7];
  std::copy(bounds, bounds + 6, kept);
  kept[6] = static_cast<double>(now.GetMTime());  // exact: far below 2^53
  poly->GetInformation()->Set(kept_cells_bounds(), kept, 7);
}

void SurfaceMapper::ComputeBounds() {
  vtkPolyData* poly = GetInput();
  if (poly) {
    vtkInformation* info = poly->GetInformation();
    const double* kept = info->Has(kept_cells_bounds()) ? info->Get(kept_cells_bounds()) : nullptr;
    if (kept && static_cast<double>(poly->GetMeshMTime()) <= kept[6]) {
      std::copy(kept, kept + 6, Bounds);
      return;
    }
  }
  Superclass::ComputeBounds();
}

void SurfaceMapper::ReleaseGraphicsResources(vtkWindow* window) {
  built_.clear();
  Superclass::ReleaseGraphicsResources(window);
}

}  // namespace deepcut::studio
