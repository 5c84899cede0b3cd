// SPDX-License-Identifier: MIT
#pragma once
// Small meshes built in code (pmp's tests/helpers.h) and invariant checks shared by the tests.

#include <string>
#include <vector>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/edit_log.h"
#include "deepcut/core/model.h"
#include "deepcut/core/ops/op_status.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut::test {

/// nx x ny quads split into triangles in the xy plane, [0,1]^2; per-corner UVs equal to xy,
/// with a UV seam down the middle column (u shifted by +1 right of x = 0.5); skinned to two
/// joints blending along x.
SurfaceMesh make_grid(int nx, int ny);

/// Closed cylinder (tube with capped ends), consistently outward oriented.
SurfaceMesh make_tube(int around, int along, float radius = 1.0f, float length = 2.0f);

/// A needle found by the random sequences: a corner X = (0, 1, 0) fanned to four points on the
/// line x = 1 (y = 0.5, 1, the next float above 1, 1.5), three faces. The middle face is a
/// needle whose two far corners lie one float step apart, so a tool crossing it splits both
/// long edges at one parameter and the two new points round to one position.
SurfaceMesh make_needle_fan();

/// A model with one skinned tube along +y and a two-joint chain with a rotation animation.
Model make_skinned_tube_model();

/// make_skinned_tube_model with corner normals and two morph targets, so skinning and morphing
/// act together: target 0 "swell" widens the middle of the tube (radial POSITION deltas, and a
/// NORMAL delta (0, 0.25, 0) on every corner), target 1 "lean" pushes it along +x, more the higher
/// the vertex. Mesh weights (0.1, 0.2). Animation 0 bends the tip joint (identity at t = 0 and 2,
/// 60 degrees at t = 1) and drives the weights linearly: (0.5, 0.8) at t = 0, (1, 0) at t = 1,
/// (0, 1) at t = 2.
Model make_morph_tube_model();

/// Checks mesh consistency and weights (gtest failures, not exceptions).
void expect_valid(const SurfaceMesh& mesh, std::size_t joint_count = 0);

/// Vertices whose live faces form two or more fans (faces joined through an edge at the vertex)
/// meeting only at the vertex, in id order: pinched (non-manifold) vertices.
std::vector<VertexId> pinched_vertices(const SurfaceMesh& mesh);

/// Incremental adjacency equals the full rebuild.
void expect_adjacency_matches_rebuild(const Adjacency& incremental, const SurfaceMesh& mesh);

/// After an operation on `mesh` that returned `status` and `log`: expects it succeeded, makes
/// `adj` (the adjacency before it) follow the log, and expects `adj` to equal a rebuild and the
/// mesh to be valid. Does nothing more when the operation failed.
void follow_checked(Adjacency& adj, const SurfaceMesh& mesh, OpStatus status, const EditLog& log);

/// The point (s, r) of the parallelogram a + s (b - a) + r (c - a), folded into the triangle
/// abc: for s, r uniform in [0, 1] it is uniform over the triangle.
glm::vec3 point_in_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float s, float r);

/// Every model file under assets/ (sorted), as absolute paths.
std::vector<std::string> asset_models();

/// The static (unrigged) meshes of the robustness suite, as absolute paths: assets/models/spot
/// (always), then the scanned meshes of ../shared/models/local-only/ that are present (never
/// copied into the project: their terms forbid it) - Stanford bunny (holes, unreferenced
/// vertices), libigl bunny (.off), fandisk (.off, sharp features), fertility (.off, genus 4),
/// horse (binary .ply, ~97K triangles), armadillo (.obj, ~86K triangles), the cage-deformation
/// cactus (.obj, three open parts with UVs). Load them with `plugins::read_model` (link
/// deepcut::formats, which needs the VTK build).
std::vector<std::string> static_models();

}  // namespace deepcut::test
