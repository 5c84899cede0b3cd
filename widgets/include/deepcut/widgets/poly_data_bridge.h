// SPDX-License-Identifier: MIT
#pragma once
/// @file poly_data_bridge.h
/// The only conversion between deepcut's SurfaceMesh and vtkPolyData.

#include <vector>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "deepcut/core/surface_mesh.h"

namespace deepcut {

struct PolyDataOptions {
  /// Positions to use instead of the mesh's bind positions (e.g. the posed ones), one per vertex.
  const std::vector<glm::vec3>* positions = nullptr;
  /// Split vertices where corner attributes differ (UV seams, hard normals), as a renderer needs;
  /// off gives one point per welded vertex and drops corner attributes.
  bool split_corners = true;
};

/// Converts the live faces of `mesh` to triangles in a vtkPolyData. Point data arrays:
/// "vertex_id" (the SurfaceMesh vertex of each point), "joints0"/"weights0" when skinned,
/// and with `split_corners` also "uv0" (texture coordinates) and "normal" (normals).
/// Cell data: "face_id" (the SurfaceMesh face of each triangle).
/// @param mesh  the mesh; @param options  see PolyDataOptions (defaults: bind pose, split corners).
vtkSmartPointer<vtkPolyData> to_poly_data(const SurfaceMesh& mesh, const PolyDataOptions& options = {});

/// Builds a SurfaceMesh from a vtkPolyData's triangles (polygons are fan-triangulated, other
/// cells ignored). Points become vertices one to one.
/// @throws Error{InvalidInput} if a point is not finite.
SurfaceMesh from_poly_data(vtkPolyData* poly);

}  // namespace deepcut
