// SPDX-License-Identifier: MIT
#pragma once
/// @file surface_mapper.h
/// The mapper of a model's surface. VTK 9.1 builds a triangle index buffer cell by cell, each
/// triangle's three points compared to leave out degenerate ones, into a vector that grows as
/// it goes: at 1M triangles about a fifth of the first frame after opening (and of the frame
/// after a cut). A surface of triangles only, drawn filled with nothing read per cell, needs no
/// more than its connectivity narrowed to 32 bits: this mapper converts it over the pool
/// straight into the index buffer, mapped for writing (no array of its own, no copy). A
/// degenerate triangle it keeps covers no pixel, so the frame is the same. Anything else (edges, wireframe,
/// points, lines or strips, cell colours or normals, a hardware selection) is VTK's own build. VTK 9.1 builds
/// the index buffers again with every upload, new positions alone included; this one only when the cells (or
/// their arrays) were marked modified. Its bounds are the cells' bounds kept with the data
/// (keep_cells_bounds) while its points and cells are unchanged since, else VTK's pass over the cells.

#include <vtkOpenGLPolyDataMapper.h>

#include <string>

namespace deepcut::studio {

class SurfaceMapper : public vtkOpenGLPolyDataMapper {
 public:
  static SurfaceMapper* New();
  vtkTypeMacro(SurfaceMapper, vtkOpenGLPolyDataMapper)
  void ReleaseGraphicsResources(vtkWindow* window) override;
  /// Keeps `bounds` with `poly` as the bounds of the points its cells use, known to the caller
  /// (what vtkPolyData::GetCellsBounds would compute): this mapper's bounds while `poly`'s points
  /// and cells stay unchanged (its GetMeshMTime), in place of VTK's pass over every cell.
  static void keep_cells_bounds(vtkPolyData* poly, const double bounds[6]);

 protected:
  SurfaceMapper() = default;
  void BuildIBO(vtkRenderer* ren, vtkActor* act, vtkPolyData* poly) override;
  /// The bounds kept with the input (keep_cells_bounds) while they hold, else VTK's.
  void ComputeBounds() override;
  /// Whether the triangle buffer is written mapped (else narrowed into an array and uploaded,
  /// as where a driver does not map it), and whether the last one built here was.
  bool map_uploads_ = true;
  bool last_mapped_ = false;

 private:
  /// Whether the triangles' connectivity alone makes the index buffers VTK would draw with.
  bool triangles_only(vtkRenderer* ren, vtkActor* act, vtkPolyData* poly);
  /// The cells the triangle buffer was last built from here; empty while VTK's own build (or
  /// none) is current.
  std::string built_;
};

}  // namespace deepcut::studio
