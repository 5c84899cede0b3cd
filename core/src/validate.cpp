// SPDX-License-Identifier: MIT
#include "deepcut/core/validate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <set>
#include <string>
#include <unordered_set>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/skinning.h"
#include "io/import_problems.h"

namespace deepcut {
namespace {

std::string where(const Model& model, std::size_t m, std::size_t p) {
  const auto& name = model.meshes[m].name;
  return "mesh " + std::to_string(m) + (name.empty() ? "" : " '" + name + "'") + " primitive " + std::to_string(p);
}

// Joint count of the skin each mesh is drawn with (-1 when unskinned).
std::vector<int> mesh_joint_counts(const Model& model) {
  std::vector<int> out(model.meshes.size(), -1);
  for (const auto& n : model.nodes)
    if (n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < out.size() && n.skin >= 0 &&
        static_cast<std::size_t>(n.skin) < model.skins.size())
      out[n.mesh] = static_cast<int>(model.skins[n.skin].joints.size());
  return out;
}

// Vertices whose faces form more than one fan (faces joined through edges at the vertex), e.g. two
// surfaces that touch only at that vertex (a bow tie).
std::size_t count_nonmanifold_vertices(const SurfaceMesh& mesh, const Adjacency& adj) {
  std::size_t count = 0;
  std::vector<std::uint32_t> parent;
  for (std::uint32_t v = 0; v < adj.vertex_count(); ++v) {
    const auto& faces = adj.vertex_faces(VertexId(v));
    if (faces.size() < 2) continue;
    parent.resize(faces.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    auto slot = [&](FaceId f) {
      return static_cast<std::uint32_t>(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin());
    };
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const auto& t = mesh.face(faces[i]);
      for (const VertexId u : t) {
        if (u.index == v) continue;
        for (const FaceId g : adj.edge_faces(VertexId(v), u)) {
          const auto a = root(static_cast<std::uint32_t>(i)), b = root(slot(g));
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
    std::size_t fans = 0;
    for (std::uint32_t i = 0; i < faces.size(); ++i) fans += root(i) == i;
    count += fans > 1;
  }
  return count;
}

// Faces using the same three vertices as an earlier face (in either winding).
std::size_t count_duplicate_faces(const SurfaceMesh& mesh) {
  struct Hash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const noexcept {
      return (std::size_t(k[0]) * 0x9E3779B97F4A7C15ull) ^ (std::size_t(k[1]) * 0xC2B2AE3D27D4EB4Full) ^ k[2];
    }
  };
  std::unordered_set<std::array<std::uint32_t, 3>, Hash> seen;
  std::size_t count = 0;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    std::array<std::uint32_t, 3> k{t[0].index, t[1].index, t[2].index};
    std::sort(k.begin(), k.end());
    count += !seen.insert(k).second;
  });
  return count;
}

// Faces whose three corner normals all point against the face's winding (its geometric normal).
std::size_t count_inverted_normal_faces(const SurfaceMesh& mesh) {
  const auto* normals = mesh.corner_attrs().find<glm::vec3>(attr::kNormal);
  if (!normals) return 0;
  const auto& pos = mesh.positions();
  std::size_t count = 0;
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const glm::dvec3 a(pos[t[0].index]), b(pos[t[1].index]), c(pos[t[2].index]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) == 0.0) return;
    bool against = true;
    for (int k = 0; k < 3; ++k) against = against && glm::dot(n, glm::dvec3((*normals)[SurfaceMesh::corner(f, k)])) < 0.0;
    count += against;
  });
  return count;
}

}  // namespace

ModelStats compute_stats(const Model& model) {
  ModelStats s;
  s.nodes = model.nodes.size();
  s.meshes = model.meshes.size();
  s.skins = model.skins.size();
  std::set<int> joints;
  for (const auto& skin : model.skins) joints.insert(skin.joints.begin(), skin.joints.end());
  s.joints = joints.size();
  s.animations = model.animations.size();
  s.materials = model.materials.size();
  s.textures = model.textures.size();
  s.images = model.images.size();
  for (const auto& mesh : model.meshes)
    for (const auto& prim : mesh.primitives) {
      ++s.primitives;
      s.gltf_vertices += prim.gltf_vertices ? prim.gltf_vertices : prim.mesh.vertex_count();
      s.triangles += prim.mesh.face_count();
      const auto adj = Adjacency::build(prim.mesh);
      std::size_t used = 0;
      for (std::uint32_t v = 0; v < adj.vertex_count(); ++v) used += !adj.vertex_faces(VertexId(v)).empty();
      s.welded_vertices += used;
      s.boundary_edges += adj.boundary_edges().size();
      s.nonmanifold_edges += adj.nonmanifold_edges().size();
      s.seam_edges += adj.seam_edges(prim.mesh).size();
      s.components += adj.component_count();
    }
  s.bounds = world_bounds(model, rest_pose(model));
  return s;
}

namespace {

// Weights not summing to 1 and influences naming a joint past the skin, in one primitive.
struct SkinCounts {
  std::size_t unnormalised = 0, out_of_range = 0;
};

SkinCounts count_skin_problems(const SurfaceMesh& mesh, int joint_count) {
  SkinCounts out;
  const auto& va = mesh.vertex_attrs();
  const auto* j0 = va.find<glm::u16vec4>(attr::kJoints0);
  const auto* w0 = va.find<glm::vec4>(attr::kWeights0);
  const auto* j1 = va.find<glm::u16vec4>(attr::kJoints1);
  const auto* w1 = va.find<glm::vec4>(attr::kWeights1);
  if (!j0 || !w0) return out;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    double sum = 0.0;
    auto check = [&](const glm::u16vec4& j, const glm::vec4& w) {
      for (int c = 0; c < 4; ++c) {
        sum += w[c];
        if (w[c] > 0.0f && joint_count >= 0 && j[c] >= joint_count) ++out.out_of_range;
      }
    };
    check((*j0)[v], (*w0)[v]);
    if (j1 && w1) check((*j1)[v], (*w1)[v]);
    if (std::abs(sum - 1.0) > 1e-3) ++out.unnormalised;
  }
  return out;
}

// The checks of one primitive, added to `out` at `place`.
void check_primitive(const SurfaceMesh& mesh, int joint_count, const std::string& place, std::vector<ImportProblem>& out) {
  using io_detail::add_problem;
  std::size_t degenerate = 0, nonfinite = 0;
  const auto& pos = mesh.positions();
  for (const auto& q : pos)
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) ++nonfinite;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    const glm::dvec3 a(pos[t[0].index]), b(pos[t[1].index]), c(pos[t[2].index]);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || glm::length(glm::cross(b - a, c - a)) == 0.0) ++degenerate;
  });
  if (mesh.face_count() == 0)
    add_problem(out, "no-triangles", 1,
                {"primitive has no triangles (left out on export)", "primitives have no triangles (left out on export)"}, place);
  const auto adj = Adjacency::build(mesh);
  const std::size_t inverted = count_inverted_normal_faces(mesh);
  const SkinCounts skin = count_skin_problems(mesh, joint_count);
  add_problem(out, "nonmanifold-edges", adj.nonmanifold_edges().size(),
              {"non-manifold edge (more than two triangles)", "non-manifold edges (more than two triangles)"}, place);
  add_problem(out, "nonmanifold-vertices", count_nonmanifold_vertices(mesh, adj),
              {"non-manifold vertex (surfaces that touch only at a vertex)",
               "non-manifold vertices (surfaces that touch only at a vertex)"},
              place);
  add_problem(out, "duplicate-triangles", count_duplicate_faces(mesh),
              {"duplicate triangle (same three vertices)", "duplicate triangles (same three vertices)"}, place);
  add_problem(out, "inverted-normals", inverted,
              {"triangle has normals pointing against its winding (inverted normals)",
               "triangles have normals pointing against their winding (inverted normals)"},
              inverted ? place + " (" + std::to_string(inverted) + " of " + std::to_string(mesh.face_count()) + ")" : place);
  add_problem(out, "degenerate-triangles", degenerate, {"degenerate triangle", "degenerate triangles"}, place);
  add_problem(out, "nonfinite-positions", nonfinite, {"position is not finite", "positions are not finite"}, place);
  add_problem(out, "weights-unnormalised", skin.unnormalised,
              {"vertex has weights not summing to 1", "vertices have weights not summing to 1"}, place);
  add_problem(out, "joints-out-of-range", skin.out_of_range,
              {"influence names a joint past the skin", "influences name a joint past the skin"}, place);
  if (mesh.vertex_attrs().find<glm::u16vec4>(attr::kJoints0) && joint_count < 0)
    add_problem(out, "skin-weights-without-skin", 1,
                {"primitive has skin weights but no node draws it with a skin",
                 "primitives have skin weights but no node draws them with a skin"},
                place);
}

}  // namespace

std::vector<ImportProblem> model_problems(const Model& model) {
  std::vector<ImportProblem> out = model.import_problems;
  const auto joint_counts = mesh_joint_counts(model);
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p)
      check_primitive(model.meshes[m].primitives[p].mesh, joint_counts[m], where(model, m, p), out);
  return out;
}

std::vector<std::string> find_problems(const Model& model) {
  std::vector<std::string> out;
  for (const auto& p : model_problems(model)) out.push_back(p.message);
  return out;
}

void validate_mesh(const SurfaceMesh& mesh, std::size_t joint_count) {
  auto fail = [](const std::string& what) { throw Error(ErrorCode::InvariantViolated, "validate_mesh: " + what); };
  const auto nv = mesh.vertex_count();
  if (mesh.face_attrs().size() != mesh.face_slots()) fail("face attribute size differs from the face count");
  if (mesh.corner_attrs().size() != 3 * mesh.face_slots()) fail("corner attribute size differs from 3 x face count");
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    for (auto v : t)
      if (v.index >= nv) fail("face " + std::to_string(f.index) + " uses vertex " + std::to_string(v.index) + " past the end");
  });
  for (std::size_t v = 0; v < nv; ++v) {
    const auto& p = mesh.positions()[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) fail("vertex " + std::to_string(v) + " is not finite");
  }
  const auto& va = mesh.vertex_attrs();
  const auto* j0 = va.find<glm::u16vec4>(attr::kJoints0);
  const auto* w0 = va.find<glm::vec4>(attr::kWeights0);
  if (j0 && w0) {
    const auto* j1 = va.find<glm::u16vec4>(attr::kJoints1);
    const auto* w1 = va.find<glm::vec4>(attr::kWeights1);
    for (std::size_t v = 0; v < nv; ++v) {
      double sum = 0.0;
      auto check = [&](const glm::u16vec4& j, const glm::vec4& w) {
        for (int c = 0; c < 4; ++c) {
          if (!(w[c] >= 0.0f)) fail("vertex " + std::to_string(v) + " has a negative or NaN weight");
          sum += w[c];
          if (w[c] > 0.0f && joint_count > 0 && j[c] >= joint_count) fail("vertex " + std::to_string(v) + " names a joint past the skin");
        }
      };
      check((*j0)[v], (*w0)[v]);
      if (j1 && w1) check((*j1)[v], (*w1)[v]);
      if (std::abs(sum - 1.0) > 1e-4) fail("vertex " + std::to_string(v) + " weights sum to " + std::to_string(sum));
    }
  }
}

}  // namespace deepcut
