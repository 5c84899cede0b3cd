// SPDX-License-Identifier: MIT
#include "deepcut/core/io/static_mesh.h"

#include <cmath>
#include <cstring>
#include <unordered_map>

#include "deepcut/core/attributes.h"
#include "deepcut/core/errors.h"

namespace deepcut {
namespace {

struct PositionKey {
  std::uint32_t bits[3];
  bool operator==(const PositionKey& o) const { return std::memcmp(bits, o.bits, sizeof(bits)) == 0; }
};

struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    std::size_t h = 1469598103934665603ull;
    for (std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
    return h;
  }
};

PositionKey key_of(const glm::vec3& p) {
  PositionKey k{};
  for (int c = 0; c < 3; ++c) {
    const float f = p[c] + 0.0f;  // -0 == +0
    std::memcpy(&k.bits[c], &f, sizeof(float));
  }
  return k;
}

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

}  // namespace

Model make_static_model(const StaticMesh& in, const std::string& name, const std::string& file) {
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

  Model model;
  model.import_notes = in.notes;
  const auto note = [&](const std::string& what) { model.import_notes.push_back(what); };

  // Weld equal positions; triangles that then repeat a vertex go; the vertices the kept
  // triangles use are numbered in order of first use.
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> welded;
  welded.reserve(np);
  std::vector<std::uint32_t> point_to_weld(np, kInvalidIndex);
  std::vector<std::uint32_t> weld_point;  // a point of each welded position
  std::vector<std::array<std::uint32_t, 3>> kept;  // welded ids
  std::vector<std::array<std::uint32_t, 3>> corners;  // the points each corner came from
  kept.reserve(in.triangles.size());
  corners.reserve(in.triangles.size());
  std::size_t repeated = 0;
  for (const auto& t : in.triangles) {
    std::array<std::uint32_t, 3> w{};
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& id = point_to_weld[t[k]];
      if (id == kInvalidIndex) {
        const auto [it, added] = welded.emplace(key_of(in.positions[t[k]]), static_cast<std::uint32_t>(weld_point.size()));
        if (added) weld_point.push_back(t[k]);
        id = it->second;
      }
      w[k] = id;
    }
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
      ++repeated;
      continue;
    }
    kept.push_back(w);
    corners.push_back(t);
  }
  if (kept.empty()) fail("every face repeats a vertex (nothing to draw)");
  std::vector<std::uint32_t> weld_to_vertex(weld_point.size(), kInvalidIndex);
  std::vector<glm::vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  triangles.reserve(kept.size());
  for (const auto& w : kept) {
    std::array<std::uint32_t, 3> v{};
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& id = weld_to_vertex[w[k]];
      if (id == kInvalidIndex) {
        id = static_cast<std::uint32_t>(positions.size());
        positions.push_back(in.positions[weld_point[w[k]]] + glm::vec3(0.0f));
      }
      v[k] = id;
    }
    triangles.push_back(v);
  }
  // Points whose position a kept triangle uses (directly or through a weld) are referenced.
  std::size_t referenced = 0;
  for (std::uint32_t id : point_to_weld) referenced += id != kInvalidIndex && weld_to_vertex[id] != kInvalidIndex;
  if (repeated) note(plural(repeated, "face repeats a vertex", "faces repeat a vertex") + " (dropped)");
  if (referenced < np) note(plural(np - referenced, "unreferenced vertex", "unreferenced vertices") + " dropped");

  Primitive prim;
  prim.gltf_vertices = np;
  prim.welded_merged = referenced - positions.size();
  SurfaceMesh& mesh = prim.mesh;
  mesh.reserve(positions.size(), triangles.size());
  for (const glm::vec3& p : positions) mesh.add_vertex(p);
  for (const auto& t : triangles) mesh.add_face(VertexId(t[0]), VertexId(t[1]), VertexId(t[2]));
  const std::size_t nv = positions.size();
  mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints0, glm::u16vec4(0)).resize(nv);
  mesh.vertex_attrs().add<glm::vec4>(attr::kWeights0, glm::vec4(1.0f, 0.0f, 0.0f, 0.0f)).resize(nv);

  // Per-point attributes become corner attributes: a seam keeps both sides' values.
  const auto corner_values = [&](const auto& values, auto& array) {
    for (std::size_t f = 0; f < corners.size(); ++f)
      for (int k = 0; k < 3; ++k) array[3 * f + std::size_t(k)] = values[corners[f][std::size_t(k)]];
  };
  if (!in.uvs.empty()) {
    if (all_finite(in.uvs)) corner_values(in.uvs, mesh.corner_attrs().add<glm::vec2>(attr::kUv0));
    else note("texture coordinates dropped (some are not finite)");
  }
  if (!in.colors.empty()) {
    if (all_finite(in.colors)) {
      std::vector<glm::vec4> clamped(in.colors.size());
      for (std::size_t i = 0; i < clamped.size(); ++i) clamped[i] = glm::clamp(in.colors[i], 0.0f, 1.0f);
      corner_values(clamped, mesh.corner_attrs().add<glm::vec4>(attr::kColor0, glm::vec4(1.0f)));
    } else {
      note("vertex colours dropped (some are not finite)");
    }
  }
  if (!in.normals.empty()) {
    // A zero or non-finite normal takes its face's normal (the file gave no usable direction).
    auto& normals = mesh.corner_attrs().add<glm::vec3>(attr::kNormal);
    corner_values(in.normals, normals);
    std::size_t replaced = 0;
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        glm::vec3& n = normals[3 * f + std::size_t(k)];
        const float len = glm::length(n);
        if (std::isfinite(len) && len > 1e-12f) {
          n /= len;
          continue;
        }
        const glm::vec3 a = positions[triangles[f][0]], b = positions[triangles[f][1]], c = positions[triangles[f][2]];
        const glm::vec3 face = glm::cross(b - a, c - a);
        const float face_len = glm::length(face);
        n = std::isfinite(face_len) && face_len > 0.0f ? face / face_len : glm::vec3(0.0f, 0.0f, 1.0f);
        ++replaced;
      }
    }
    if (replaced) note(plural(replaced, "normal was", "normals were") + " zero or not finite (replaced by the face normal)");
  }

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
  return model;
}

}  // namespace deepcut
