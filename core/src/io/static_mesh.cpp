// SPDX-License-Identifier: MIT
#include "deepcut/core/io/static_mesh.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/attributes.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/weld.h"
#include "io/import_problems.h"

namespace deepcut {
namespace {

template <class T>
bool all_finite(const std::vector<T>& values) {
  for (const T& v : values)
    for (int c = 0; c < T::length(); ++c)
      if (!std::isfinite(v[c])) return false;
  return true;
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The mesh as the reader found it: point i is vertex i (-0 coordinates read as +0), triangle t
// is face t, and the per-point attributes become corner attributes (uvs and colours only when
// finite, colours clamped to [0, 1]; normals as given).
SurfaceMesh file_mesh(const StaticMesh& in, bool uvs_ok, bool colors_ok) {
  SurfaceMesh mesh;
  const std::size_t np = in.positions.size();
  mesh.reserve(np, in.triangles.size());
  mesh.vertex_attrs().resize(np);
  for (std::size_t i = 0; i < np; ++i) mesh.positions()[i] = in.positions[i] + glm::vec3(0.0f);
  for (const auto& t : in.triangles) mesh.add_face(VertexId(t[0]), VertexId(t[1]), VertexId(t[2]));
  const auto corner_values = [&](const auto& values, auto& array) {
    for (std::size_t f = 0; f < in.triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) array[3 * f + std::size_t(k)] = values[in.triangles[f][std::size_t(k)]];
  };
  if (!in.uvs.empty() && uvs_ok) corner_values(in.uvs, mesh.corner_attrs().add<glm::vec2>(attr::kUv0));
  if (!in.colors.empty() && colors_ok) {
    std::vector<glm::vec4> clamped(in.colors.size());
    for (std::size_t i = 0; i < clamped.size(); ++i) clamped[i] = glm::clamp(in.colors[i], 0.0f, 1.0f);
    corner_values(clamped, mesh.corner_attrs().add<glm::vec4>(attr::kColor0, glm::vec4(1.0f)));
  }
  if (!in.normals.empty()) corner_values(in.normals, mesh.corner_attrs().add<glm::vec3>(attr::kNormal));
  return mesh;
}

// Throws InvalidInput (naming `file`) unless `in` has faces, finite points, faces naming points
// it has, and per-point attributes either absent or one per point.
void check_static_mesh(const StaticMesh& in, const std::string& file) {
  const auto fail = [&](const std::string& what) { throw Error(ErrorCode::InvalidInput, file + ": " + what); };
  const std::size_t np = in.positions.size();
  if (in.triangles.empty()) fail(np == 0 ? "no vertices and no faces" : "no faces (only " + plural(np, "point", "points") + ")");
  for (std::size_t i = 0; i < np; ++i)
    if (!std::isfinite(in.positions[i].x) || !std::isfinite(in.positions[i].y) || !std::isfinite(in.positions[i].z))
      fail("vertex " + std::to_string(i) + " is not finite (NaN or Inf)");
  for (std::size_t t = 0; t < in.triangles.size(); ++t)
    for (std::uint32_t v : in.triangles[t])
      if (v >= np)
        fail("face " + std::to_string(t) + " uses vertex " + std::to_string(v) + ", past the " +
             plural(np, "vertex", "vertices"));
  const auto check_size = [&](std::size_t n, const char* what) {
    if (n != 0 && n != np)
      fail(std::string(what) + " count " + std::to_string(n) + " differs from the vertex count " + std::to_string(np));
  };
  check_size(in.normals.size(), "normal");
  check_size(in.uvs.size(), "texture coordinate");
  check_size(in.colors.size(), "colour");
}

// Makes the corner normals of `mesh` unit length; a zero or non-finite one takes its face's normal
// (the file gave no usable direction). Returns how many were replaced.
// @pre `mesh` has corner normals (attr::kNormal).
std::size_t unit_corner_normals(SurfaceMesh& mesh) {
  auto& normals = mesh.corner_attrs().get<glm::vec3>(attr::kNormal);
  const auto& positions = mesh.positions();
  std::size_t replaced = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const Triangle& t = mesh.face(FaceId(static_cast<std::uint32_t>(f)));
    for (int k = 0; k < 3; ++k) {
      glm::vec3& n = normals[3 * f + std::size_t(k)];
      const float len = glm::length(n);
      if (std::isfinite(len) && len > 1e-12f) {
        n /= len;
        continue;
      }
      const glm::vec3 a = positions[t[0].index], b = positions[t[1].index], c = positions[t[2].index];
      const glm::vec3 face = glm::cross(b - a, c - a);
      const float face_len = glm::length(face);
      n = std::isfinite(face_len) && face_len > 0.0f ? face / face_len : glm::vec3(0.0f, 0.0f, 1.0f);
      ++replaced;
    }
  }
  return replaced;
}

// The primitive of `in` (checked): the mesh as the file stores it (one vertex per point, -0
// coordinates read as +0; per-point attributes on the corners, so seams survive), welded by
// position: triangles that then repeat a vertex go, and the vertices the kept triangles use are
// numbered in order of first use. Every vertex bound to joint 0 alone; unit corner normals. What
// it dropped or replaced is added to `problems`.
Primitive static_primitive(const StaticMesh& in, const std::string& file,
                           std::vector<ImportProblem>& problems) {
  const auto problem = [&](const char* kind, std::size_t count, const io_detail::Counted& what) {
    io_detail::add_problem(problems, kind, count, what);
  };
  const bool uvs_ok = all_finite(in.uvs), colors_ok = all_finite(in.colors);
  Primitive prim;
  prim.gltf_vertices = in.positions.size();
  SurfaceMesh& mesh = prim.mesh;
  mesh = file_mesh(in, uvs_ok, colors_ok);
  const WeldReport welded = weld(mesh, {WeldKey::Position, /*drop_repeating_faces=*/true});
  if (mesh.face_count() == 0)
    throw Error(ErrorCode::InvalidInput, file + ": every face repeats a vertex (nothing to draw)");
  if (welded.faces_dropped)
    problem("faces-repeating-a-vertex-dropped", welded.faces_dropped,
            {"face repeats a vertex (dropped)", "faces repeat a vertex (dropped)"});
  if (welded.dropped)
    problem("unreferenced-vertices-dropped", welded.dropped, {"unreferenced vertex dropped", "unreferenced vertices dropped"});
  prim.welded_merged = welded.merged;
  const std::size_t nv = mesh.vertex_count();
  mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints0, glm::u16vec4(0)).resize(nv);
  mesh.vertex_attrs().add<glm::vec4>(attr::kWeights0, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f)).resize(nv);

  if (!in.uvs.empty() && !uvs_ok)
    problem("uvs-dropped", in.uvs.size(),
            {"texture coordinate dropped (some are not finite)", "texture coordinates dropped (some are not finite)"});
  if (!in.colors.empty() && !colors_ok)
    problem("colours-dropped", in.colors.size(),
            {"vertex colour dropped (some are not finite)", "vertex colours dropped (some are not finite)"});
  if (in.normals.empty()) return prim;
  if (const std::size_t replaced = unit_corner_normals(mesh))
    problem("normals-replaced", replaced,
            {"normal was zero or not finite (replaced by the face normal)",
             "normals were zero or not finite (replaced by the face normal)"});
  return prim;
}

// Puts `prim` into `model` as its one mesh `name`, drawn by a node skinned to a root joint at the
// origin, in the one scene.
void add_rigged_mesh(Model& model, Primitive prim, const std::string& name) {
  Mesh out_mesh;
  out_mesh.name = name;
  out_mesh.primitives.push_back(std::move(prim));
  model.meshes.push_back(std::move(out_mesh));

  Node mesh_node;
  mesh_node.name = name;
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  Node root;
  root.name = "root";
  model.nodes = {std::move(mesh_node), std::move(root)};
  Skin skin;
  skin.name = name + " skin";
  skin.joints = {1};
  skin.inverse_bind_matrices = {glm::mat4(1.0f)};
  skin.skeleton = 1;
  model.skins.push_back(std::move(skin));
  model.scenes = {{0, 1}};
  model.default_scene = 0;
}

}  // namespace

Model make_static_model(const StaticMesh& in, const std::string& name, const std::string& file) {
  check_static_mesh(in, file);
  Model model;
  model.import_problems = in.problems;
  add_rigged_mesh(model, static_primitive(in, file, model.import_problems), name);
  return model;
}

}  // namespace deepcut
