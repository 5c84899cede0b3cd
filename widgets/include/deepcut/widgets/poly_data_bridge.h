// SPDX-License-Identifier: MIT
#pragma once
/// @file poly_data_bridge.h
/// The only conversion between deepcut's SurfaceMesh and vtkPolyData.

#include <vector>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <glm/gtc/type_precision.hpp>

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
/// "vertex_id" (the SurfaceMesh vertex of each point), "corner_id" (one corner, 3 * face + k,
/// that the point stands for), "joints0"/"weights0" when skinned, and with `split_corners`
/// also "uv0" (texture coordinates) and "normal" (normals).
/// Cell data: "face_id" (the SurfaceMesh face of each triangle).
/// @param mesh  the mesh; @param options  see PolyDataOptions (defaults: bind pose, split corners).
vtkSmartPointer<vtkPolyData> to_poly_data(const SurfaceMesh& mesh, const PolyDataOptions& options = {});

/// Moves the points of a poly data made by `to_poly_data` to new vertex positions, and when
/// `corner_normals` is given (one per corner, e.g. `posed_normals`) sets its normals too.
/// Marks the data modified.
/// @param positions  one per vertex of the mesh the poly data was made from.
/// @pre `poly` came from `to_poly_data` of that mesh (it has "vertex_id" and "corner_id").
/// @throws Error{InvalidArgument} if the arrays are missing or an index is out of range.
void update_poly_data_points(vtkPolyData* poly, const std::vector<glm::vec3>& positions,
                             const std::vector<glm::vec3>* corner_normals = nullptr);

/// Sets RGB point colours from one colour per mesh vertex (through "vertex_id"), as the active
/// scalars ("colors", unsigned char).
/// @throws Error{InvalidArgument} if a point's vertex has no colour.
void set_vertex_colors(vtkPolyData* poly, const std::vector<glm::u8vec3>& vertex_colors);

/// Sets RGB cell colours from one colour per mesh face slot (through "face_id"), as the active
/// cell scalars ("colors", unsigned char).
/// @throws Error{InvalidArgument} if a cell's face has no colour.
void set_face_colors(vtkPolyData* poly, const std::vector<glm::u8vec3>& face_colors);

/// Removes the colours set by `set_vertex_colors` / `set_face_colors`.
void clear_colors(vtkPolyData* poly);

/// Builds a SurfaceMesh from a vtkPolyData's triangles (polygons are fan-triangulated, other
/// cells ignored). Points become vertices one to one.
/// @throws Error{InvalidInput} if a point is not finite.
SurfaceMesh from_poly_data(vtkPolyData* poly);

}  // namespace deepcut
