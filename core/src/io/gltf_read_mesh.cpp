// SPDX-License-Identifier: MIT
// glTF import: meshes. A primitive is decoded into the mesh the file stores (one vertex per glTF
// vertex, skin influences on the vertices, every other attribute on the corners) and welded by
// the one `weld` into one topological vertex per (position, skin).
#include <algorithm>
#include <cctype>
#include <cmath>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/weld.h"
#include "io/gltf_common.h"
#include "io/gltf_reader.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

// The primitive as the file stores it: glTF vertex v is vertex v (-0 coordinates read as +0),
// triangle t is face t, and the corner attributes come from each corner's glTF vertex.
SurfaceMesh file_mesh(const std::vector<float>& pos, const std::vector<std::uint32_t>& tris, const Influences& skin,
                      const std::vector<CornerSource>& corner_sources) {
  SurfaceMesh mesh;
  const std::size_t nv = pos.size() / 3;
  mesh.reserve(nv, tris.size() / 3);
  mesh.vertex_attrs().resize(nv);
  auto& positions = mesh.positions();
  for (std::size_t v = 0; v < nv; ++v)
    positions[v] = glm::vec3(pos[3 * v] + 0.0f, pos[3 * v + 1] + 0.0f, pos[3 * v + 2] + 0.0f);  // -0 == +0
  for (std::size_t i = 0; i < tris.size(); i += 3) mesh.add_face(VertexId(tris[i]), VertexId(tris[i + 1]), VertexId(tris[i + 2]));

  const char* jn[2] = {attr::kJoints0, attr::kJoints1};
  const char* wn[2] = {attr::kWeights0, attr::kWeights1};
  for (std::size_t s = 0; s < skin.sets; ++s) {
    auto& ja = mesh.vertex_attrs().add<glm::u16vec4>(jn[s]);
    auto& wa = mesh.vertex_attrs().add<glm::vec4>(wn[s]);
    std::copy_n(skin.joints.begin() + std::ptrdiff_t(s * nv), nv, ja.data().begin());
    std::copy_n(skin.weights.begin() + std::ptrdiff_t(s * nv), nv, wa.data().begin());
  }
  const std::size_t nc = tris.size();
  for (const auto& cs : corner_sources) {
    if (cs.comps == 2) {
      auto& a = mesh.corner_attrs().add<glm::vec2>(cs.name);
      for (std::size_t c = 0; c < nc; ++c) a[c] = glm::vec2(cs.data[2 * tris[c]], cs.data[2 * tris[c] + 1]);
    } else if (cs.comps == 3) {
      auto& a = mesh.corner_attrs().add<glm::vec3>(cs.name);
      for (std::size_t c = 0; c < nc; ++c) {
        const float* d = &cs.data[3 * tris[c]];
        a[c] = glm::vec3(d[0], d[1], d[2]);
      }
    } else {
      auto& a = mesh.corner_attrs().add<glm::vec4>(cs.name, glm::vec4(1.0f));
      for (std::size_t c = 0; c < nc; ++c) {
        const float* d = &cs.data[std::size_t(cs.data_comps) * tris[c]];
        a[c] = glm::vec4(d[0], d[1], d[2], cs.data_comps == 4 ? d[3] : 1.0f);
      }
    }
  }
  return mesh;
}

}  // namespace

Primitive Reader::read_primitive(const tinygltf::Primitive& p, const std::string& where, int joint_count, std::size_t targets) {
  Primitive out;
  out.material = p.material;
  if (p.material >= 0 && static_cast<std::size_t>(p.material) >= gltf_.materials.size())
    fail(where + " uses material " + std::to_string(p.material) + ", which does not exist");
  if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP && p.mode != TINYGLTF_MODE_TRIANGLE_FAN &&
      p.mode != -1) {
    static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    fail(where + " has mode " + (p.mode >= 0 && p.mode < 4 ? names[p.mode] : std::to_string(p.mode)) +
         "; only triangle primitives are supported");
  }
  const std::vector<float> pos = read_positions(p, where);
  const std::size_t nv = pos.size() / 3;
  out.gltf_vertices = nv;
  const std::vector<std::uint32_t> tris = read_triangles(p, where, nv);
  const Influences skin = read_influences(p, where, nv, joint_count);
  const std::vector<CornerSource> corner_sources = read_corner_sources(p, where, nv);
  const std::vector<MorphTarget> morphs = read_targets(p, where, nv, tris.size(), targets);

  // Weld: one topological vertex per distinct (position, skin, morph deltas); numbered by first use.
  out.mesh = file_mesh(pos, tris, skin, corner_sources);
  add_morph_targets(out.mesh, tris, morphs);
  const WeldReport welded = weld(out.mesh, {options_.weld ? WeldKey::PositionAndSkin : WeldKey::None});
  out.welded_merged = welded.merged;
  if (welded.kept_apart)
    note(where + ": " + std::to_string(welded.kept_apart) + " vertices share a position with different skin weights" +
         (morphs.empty() ? "" : " or morph deltas") + " (kept apart)");
  if (welded.dropped) note(where + ": " + std::to_string(welded.dropped) + " unreferenced vertices dropped");
  return out;
}

std::vector<float> Reader::read_positions(const tinygltf::Primitive& p, const std::string& where) {
  auto pos_it = p.attributes.find("POSITION");
  if (pos_it == p.attributes.end()) fail(where + " has no POSITION attribute");
  int comps = 0;
  const auto pos = read_floats(pos_it->second, "POSITION", &comps);
  if (comps != 3) fail(where + ": POSITION is not VEC3");
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (!std::isfinite(pos[i])) fail(where + ": POSITION " + std::to_string(i / 3) + " is not finite (NaN or Inf)");
  return pos;
}

// Triangles as glTF vertex indices (strips and fans converted).
std::vector<std::uint32_t> Reader::read_triangles(const tinygltf::Primitive& p, const std::string& where, std::size_t nv) {
  std::vector<std::uint32_t> idx;
  if (p.indices >= 0) {
    int ic = 0;
    idx = read_uints(p.indices, "indices", &ic);
    if (ic != 1) fail(where + ": indices are not SCALAR");
    if (gltf_.accessors[p.indices].componentType == kFloat) fail(where + ": indices must be integers");
    for (std::size_t i = 0; i < idx.size(); ++i)
      if (idx[i] >= nv)
        fail(where + ": index " + std::to_string(idx[i]) + " (position " + std::to_string(i) + ") is past the " +
             std::to_string(nv) + " vertices");
  } else {
    idx.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) idx[i] = static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint32_t> tris;
  if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 2; i < idx.size(); ++i) {
      if (i % 2 == 0) tris.insert(tris.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else tris.insert(tris.end(), {idx[i - 1], idx[i - 2], idx[i]});
    }
    note(where + ": triangle strip converted to triangles");
  } else if (p.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 2; i < idx.size(); ++i) tris.insert(tris.end(), {idx[0], idx[i - 1], idx[i]});
    note(where + ": triangle fan converted to triangles");
  } else {
    if (idx.size() % 3 != 0) fail(where + ": index count " + std::to_string(idx.size()) + " is not a multiple of 3");
    tris = std::move(idx);
  }
  return tris;
}

// Up to two sets of four influences per vertex, sanitised; every repair is noted.
Influences Reader::read_influences(const tinygltf::Primitive& p, const std::string& where, std::size_t nv, int joint_count) {
  struct SkinSetData {
    std::vector<std::uint32_t> joints;
    std::vector<float> weights;
  };
  std::vector<SkinSetData> sets;
  for (int s = 0; s < 2; ++s) {
    auto j = p.attributes.find("JOINTS_" + std::to_string(s));
    auto w = p.attributes.find("WEIGHTS_" + std::to_string(s));
    if (j == p.attributes.end() || w == p.attributes.end()) break;
    SkinSetData d;
    int jc = 0, wc = 0;
    d.joints = read_uints(j->second, "JOINTS", &jc);
    d.weights = read_floats(w->second, "WEIGHTS", &wc);
    if (jc != 4 || wc != 4 || d.joints.size() != 4 * nv || d.weights.size() != 4 * nv)
      fail(where + ": JOINTS_" + std::to_string(s) + "/WEIGHTS_" + std::to_string(s) + " must be VEC4 with one per vertex");
    sets.push_back(std::move(d));
  }
  const int slots = 4 * static_cast<int>(sets.size());
  std::size_t renormalised = 0, out_of_range = 0, zero = 0, bad_weights = 0;
  Influences skin;
  skin.sets = sets.size();
  skin.joints.resize(sets.size() * nv);
  skin.weights.resize(sets.size() * nv);
  for (std::size_t v = 0; v < nv && slots > 0; ++v) {
    std::uint16_t jj[8] = {};
    float ww[8] = {};
    double sum = 0.0;
    for (int k = 0; k < slots; ++k) {
      const auto& d = sets[std::size_t(k / 4)];
      std::uint32_t joint = d.joints[4 * v + std::size_t(k % 4)];
      float weight = d.weights[4 * v + std::size_t(k % 4)];
      if (!std::isfinite(weight) || weight < 0.0f) {
        ++bad_weights;
        weight = 0.0f;
      }
      if (joint_count >= 0 && joint >= static_cast<std::uint32_t>(joint_count)) {
        // Dropped, and the slot points at joint 0: a vertex left with no weight is bound to its
        // first slot's joint, which must exist.
        out_of_range += weight > 0.0f;
        weight = 0.0f;
        joint = 0;
      }
      if (joint > 65535u) joint = 0;
      jj[k] = static_cast<std::uint16_t>(joint);
      ww[k] = weight;
      sum += weight;
    }
    if (std::abs(sum - 1.0) > 1e-3) ++renormalised;
    if (!normalize_influences(jj, ww, slots)) ++zero;
    for (std::size_t s = 0; s < sets.size(); ++s) {
      skin.joints[s * nv + v] = glm::u16vec4(jj[4 * s], jj[4 * s + 1], jj[4 * s + 2], jj[4 * s + 3]);
      skin.weights[s * nv + v] = glm::vec4(ww[4 * s], ww[4 * s + 1], ww[4 * s + 2], ww[4 * s + 3]);
    }
  }
  if (bad_weights) note(where + ": " + std::to_string(bad_weights) + " weights were negative or NaN (set to 0)");
  if (renormalised) note(where + ": " + std::to_string(renormalised) + " vertices had weights not summing to 1 (normalised)");
  if (out_of_range) note(where + ": " + std::to_string(out_of_range) + " influences named a joint past the skin (dropped)");
  if (zero) note(where + ": " + std::to_string(zero) + " vertices had no weight (bound to their first joint)");
  return skin;
}

std::vector<CornerSource> Reader::read_corner_sources(const tinygltf::Primitive& p, const std::string& where,
                                                      std::size_t nv) {
  std::vector<CornerSource> corner_sources;
  for (const auto& [name, accessor] : p.attributes) {
    if (name == "POSITION" || name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) {
      if ((name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) && name.back() > '1')
        note(where + ": " + name + " dropped (at most 8 influences are kept)");
      continue;
    }
    CornerSource cs;
    if (name == "NORMAL") { cs.name = attr::kNormal; cs.comps = 3; }
    else if (name == "TANGENT") { cs.name = attr::kTangent; cs.comps = 4; }
    else if (name == "COLOR_0") { cs.name = attr::kColor0; cs.comps = 4; }
    else if (name.rfind("TEXCOORD_", 0) == 0) {
      const std::string set = name.substr(9);
      if (set.empty() || set.size() > 2 || !std::all_of(set.begin(), set.end(), [](unsigned char c) { return std::isdigit(c); })) {
        note(where + ": attribute " + name + " dropped (not a valid glTF attribute name)");
        continue;
      }
      cs.name = attr::uv_name(std::stoi(set));
      cs.comps = 2;
    }
    else {
      note(where + ": attribute " + name + " dropped (not supported)");
      continue;
    }
    cs.data = read_floats(accessor, name.c_str(), &cs.data_comps);
    if (cs.data.size() / std::size_t(std::max(cs.data_comps, 1)) != nv) fail(where + ": " + name + " count differs from POSITION count");
    const bool ok = cs.data_comps == cs.comps || (name == "COLOR_0" && cs.data_comps == 3);
    if (!ok) fail(where + ": " + name + " has " + std::to_string(cs.data_comps) + " components");
    corner_sources.push_back(std::move(cs));
  }
  return corner_sources;
}

void Reader::read_meshes() {
  // The skin a mesh is drawn with decides the valid joint range of its influences.
  std::vector<int> mesh_joints(gltf_.meshes.size(), -1);
  for (const auto& n : model_.nodes)
    if (n.mesh >= 0 && n.skin >= 0) mesh_joints[n.mesh] = static_cast<int>(model_.skins[n.skin].joints.size());
  for (std::size_t m = 0; m < gltf_.meshes.size(); ++m) {
    const auto& g = gltf_.meshes[m];
    Mesh mesh;
    mesh.name = g.name;
    const json& r = raw_.contains("meshes") && m < raw_["meshes"].size() ? raw_["meshes"][m] : json::object();
    mesh.extras_json = dump_member(r, "extras");
    const std::string mesh_where = "mesh " + std::to_string(m) + (g.name.empty() ? "" : " '" + g.name + "'");
    const std::size_t targets = mesh_target_count(m, mesh_where);
    read_mesh_weights(mesh, m, mesh_where, targets);
    for (std::size_t p = 0; p < g.primitives.size(); ++p) {
      const std::string where = mesh_where + " primitive " + std::to_string(p);
      Primitive prim = read_primitive(g.primitives[p], where, mesh_joints[m], targets);
      if (r.contains("primitives") && p < r["primitives"].size()) prim.extras_json = dump_member(r["primitives"][p], "extras");
      mesh.primitives.push_back(std::move(prim));
    }
    model_.meshes.push_back(std::move(mesh));
  }
}

}  // namespace deepcut::gltf_detail
