// SPDX-License-Identifier: MIT
#pragma once
// The invariants every drill keeps (no surface inside the cylinder, rims on it, closed walls of
// the right volume, ...), checked on one mesh-level drill, and the measures they use.

#include <cstddef>

#include "deepcut/core/model.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut::test {

/// The cylinder's axis in double precision: axial coordinate `s` and distance `rho` from it.
struct Axis {
  glm::dvec3 a, d;
  double len, r;
  explicit Axis(const Cylinder& c);
  double s(const glm::vec3& p) const;
  double rho(const glm::vec3& p) const;
};

/// Boundary edges and directed edges used by more than one face.
struct EdgeCensus {
  std::size_t boundary = 0, inconsistent = 0;
};
EdgeCensus census(const SurfaceMesh& mesh);

/// Signed volume of the solid inside the finite cylinder, integrated along lines parallel to the
/// axis (winding number of each point): `rings` x 4 `rings` lines over the disk.
double drilled_volume(const SurfaceMesh& mesh, const Cylinder& c, int rings);

/// Smallest angle of a triangle, degrees.
double min_angle(const SurfaceMesh& mesh, const Triangle& t);

struct Checked {
  // New triangles, and those under 5 degrees: surface ones whose parent was not itself thin
  // (under 10 degrees), and wall ones.
  std::size_t surface = 0, surface_thin = 0, wall = 0, wall_thin = 0, degenerate = 0;
  bool intersected = false;
  bool all_walled = false;
  std::size_t round_holes = 0, d_holes = 0;  // holes the axis crosses: on the side, across an end plane
};

/// All the invariants of one mesh-level drill of a copy of `input` on bind positions (posed ==
/// bind), with gtest assertions. `use_index` is ignored: every drill goes through the posed
/// mesh's grid (PosedMesh::at_positions).
void check_drill_into(Checked& out, const SurfaceMesh& input, const Cylinder& cyl,
                      const DrillOptions& options, std::size_t joints, bool use_index);
Checked check_drill(const SurfaceMesh& input, const Cylinder& cyl, const DrillOptions& options,
                    std::size_t joints, bool use_index);
/// check_drill on the first primitive of an asset model (the decoded replays of random drills).
Checked check_asset_drill(const Model& model, const Cylinder& cyl, bool wall, bool use_index);

}  // namespace deepcut::test
