// SPDX-License-Identifier: MIT
#include "deepcut/core/io/gltf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <tuple>

#include "deepcut/core/operation_room.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;

std::string base64(const std::vector<unsigned char>& d) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < d.size(); i += 3) {
    const unsigned n = (unsigned(d[i]) << 16) | (i + 1 < d.size() ? unsigned(d[i + 1]) << 8 : 0u) |
                       (i + 2 < d.size() ? unsigned(d[i + 2]) : 0u);
    out += t[(n >> 18) & 63];
    out += t[(n >> 12) & 63];
    out += i + 1 < d.size() ? t[(n >> 6) & 63] : '=';
    out += i + 2 < d.size() ? t[n & 63] : '=';
  }
  return out;
}

template <class T>
void append(std::vector<unsigned char>& buf, const std::vector<T>& values) {
  const auto* p = reinterpret_cast<const unsigned char*>(values.data());
  buf.insert(buf.end(), p, p + values.size() * sizeof(T));
  while (buf.size() % 4) buf.push_back(0);
}

std::string write_text(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// A quad (two triangles) skinned to a skin WITHOUT inverseBindMatrices, positions interleaved with
// normalised-short UVs (byteStride), a sparse accessor overriding one position, weights stored as
// normalised unsigned bytes that do not sum to 255.
json quirky_gltf(std::vector<unsigned char>& buf) {
  // Interleaved: position (3 floats) + uv (2 normalised u16) = 16 bytes per vertex.
  struct V {
    float p[3];
    std::uint16_t uv[2];
  };
  std::vector<V> verts = {{{0, 0, 0}, {0, 0}}, {{1, 0, 0}, {65535, 0}}, {{1, 1, 0}, {65535, 65535}}, {{0, 1, 0}, {0, 65535}}};
  append(buf, verts);
  const std::size_t idx_off = buf.size();
  append(buf, std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3});
  const std::size_t joints_off = buf.size();
  append(buf, std::vector<std::uint8_t>{0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
  const std::size_t weights_off = buf.size();
  append(buf, std::vector<std::uint8_t>{100, 100, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0});
  const std::size_t sparse_idx_off = buf.size();
  append(buf, std::vector<std::uint16_t>{3});
  const std::size_t sparse_val_off = buf.size();
  append(buf, std::vector<float>{0, 2, 0});
  json doc;
  doc["asset"] = {{"version", "2.0"}};
  doc["scene"] = 0;
  doc["scenes"] = json::array({json{{"nodes", {0, 1}}}});
  doc["nodes"] = json::array({json{{"mesh", 0}, {"skin", 0}, {"name", "quad"}}, json{{"name", "j0"}, {"children", {2}}},
                              json{{"name", "j1"}, {"translation", {0, 1, 0}}}});
  doc["skins"] = json::array({json{{"joints", {1, 2}}}});
  json prim = {{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}, {"JOINTS_0", 3}, {"WEIGHTS_0", 4}}}, {"indices", 2}};
  doc["meshes"] = json::array({json{{"primitives", json::array({prim})}}});
  auto view = [](std::size_t offset, std::size_t length) { return json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}}; };
  json interleaved = view(0, 64);
  interleaved["byteStride"] = 16;
  doc["bufferViews"] = json::array({interleaved, view(idx_off, 6), view(joints_off, 16), view(weights_off, 16),
                                    view(sparse_idx_off, 2), view(sparse_val_off, 12)});
  json positions = {{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 2, 0}}};
  positions["sparse"] = {{"count", 1}, {"indices", {{"bufferView", 4}, {"componentType", 5123}}}, {"values", {{"bufferView", 5}}}};
  doc["accessors"] = json::array(
      {positions,
       json{{"bufferView", 0}, {"byteOffset", 12}, {"componentType", 5123}, {"normalized", true}, {"count", 4}, {"type", "VEC2"}},
       json{{"bufferView", 1}, {"componentType", 5121}, {"count", 6}, {"type", "SCALAR"}},
       json{{"bufferView", 2}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}},
       json{{"bufferView", 3}, {"componentType", 5121}, {"normalized", true}, {"count", 4}, {"type", "VEC4"}}});
  json material = {{"name", "m"}};
  material["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 2.5;
  doc["materials"] = json::array({material});
  doc["extensionsUsed"] = json::array({"KHR_materials_emissive_strength"});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  doc["buffers"] = json::array({json{{"byteLength", buf.size()}, {"uri", "data:application/octet-stream;base64," + base64(buf)}}});
  return doc;
}

// Joint indices `j` (four per vertex) as components of `type` (5121, 5123 or 5125), packed, or
// at `offset` in elements `stride` bytes apart (shorts only) with filler bytes between.
std::vector<unsigned char> joint_bytes(const std::vector<std::uint32_t>& j, int type, std::size_t stride,
                                       std::size_t offset) {
  const std::size_t size = type == 5121 ? 1 : type == 5123 ? 2 : 4, nv = j.size() / 4;
  if (stride == 0) stride = 4 * size;
  std::vector<unsigned char> out(offset + stride * nv, 0xAB);
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::uint8_t b = static_cast<std::uint8_t>(j[i]);
    const std::uint16_t h = static_cast<std::uint16_t>(j[i]);
    unsigned char* at = &out[offset + stride * (i / 4) + size * (i % 4)];
    if (size == 1)
      *at = b;
    else if (size == 2)
      std::memcpy(at, &h, 2);
    else
      std::memcpy(at, &j[i], 4);
  }
  return out;
}

// A skinned triangle soup of `nv` vertices (non-indexed) whose JOINTS_0 are stored with
// `joint_type` (5121, 5123 or 5125: bytes, shorts or 32-bit ints, the last decoded by the reader,
// not read in place); `interleaved` (shorts only) puts them at an odd byteOffset in a view of
// byteStride 12 with filler bytes between. The influences come in runs of 37 vertices, of one
// kind each (good, a negative or NaN weight, a joint past the skin, a repeated joint, no weight,
// weights not summing to 1): `kinds[k]` counts the vertices of kind k. The binary buffer is
// written beside the file.
json run_skinned_gltf(const std::string& dir, const std::string& name, std::size_t nv, int joint_type,
                      bool interleaved, std::size_t kinds[7]) {
  static const std::uint32_t joints[7][4] = {{0, 1, 0, 0}, {0, 1, 2, 0}, {1, 2, 0, 0}, {7, 1, 0, 0},
                                             {1, 1, 2, 0}, {2, 0, 0, 0}, {0, 2, 0, 0}};
  const float nan = std::nanf("");
  const float weights[7][4] = {{0.5f, 0.5f, 0, 0}, {1, -0.5f, 0, 0},        {nan, 1, 0, 0},
                               {0.5f, 0.5f, 0, 0}, {0.25f, 0.25f, 0.5f, 0}, {0, 0, 0, 0},
                               {0.3f, 0.3f, 0, 0}};
  std::vector<float> pos, w;
  std::vector<std::uint32_t> j32;
  for (int k = 0; k < 7; ++k) kinds[k] = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t t = v / 3, c = v % 3, kind = (v / 37) % 7;
    pos.insert(pos.end(), {float(t % 200 + (c == 1)), float(t / 200 + (c == 2)), 0.0f});
    j32.insert(j32.end(), joints[kind], joints[kind] + 4);
    w.insert(w.end(), weights[kind], weights[kind] + 4);
    ++kinds[kind];
  }
  std::vector<unsigned char> buf;
  append(buf, pos);
  const std::size_t weights_off = buf.size();
  append(buf, w);
  const std::size_t joints_off = buf.size();
  const std::size_t stride = interleaved ? 12 : 0, joint_offset = interleaved ? 3 : 0;
  const std::vector<unsigned char> joint_view = joint_bytes(j32, joint_type, stride, joint_offset);
  const std::size_t joints_len = joint_view.size();
  append(buf, joint_view);
  std::ofstream(dir + "/" + name + ".bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size()));
  json doc;
  doc["asset"] = {{"version", "2.0"}};
  doc["scene"] = 0;
  doc["scenes"] = json::array({json{{"nodes", {0, 1}}}});
  doc["nodes"] = json::array({json{{"mesh", 0}, {"skin", 0}}, json{{"name", "j0"}, {"children", {2, 3}}},
                              json{{"name", "j1"}, {"translation", {0, 1, 0}}}, json{{"name", "j2"}}});
  doc["skins"] = json::array({json{{"joints", {1, 2, 3}}}});
  json prim = {{"attributes", {{"POSITION", 0}, {"WEIGHTS_0", 1}, {"JOINTS_0", 2}}}};
  doc["meshes"] = json::array({json{{"primitives", json::array({prim})}}});
  auto view = [](std::size_t offset, std::size_t length) {
    return json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}};
  };
  json joints_view = view(joints_off, joints_len);
  if (stride) joints_view["byteStride"] = stride;
  doc["bufferViews"] = json::array({view(0, 12 * nv), view(weights_off, 16 * nv), joints_view});
  doc["accessors"] =
      json::array({json{{"bufferView", 0},
                        {"componentType", 5126},
                        {"count", nv},
                        {"type", "VEC3"},
                        {"min", {0, 0, 0}},
                        {"max", {200, 1000, 0}}},
                   json{{"bufferView", 1}, {"componentType", 5126}, {"count", nv}, {"type", "VEC4"}},
                   json{{"bufferView", 2},
                        {"byteOffset", joint_offset},
                        {"componentType", joint_type},
                        {"count", nv},
                        {"type", "VEC4"}}});
  doc["buffers"] = json::array({json{{"byteLength", buf.size()}, {"uri", name + ".bin"}}});
  return doc;
}

}  // namespace

TEST(GltfTest, bundled_models_match_independently_known_counts) {
  struct Known {
    const char* file;
    std::size_t vertices, welded, triangles, joints, animations;
  };
  // From the models' own documentation (shared/models/README.md), not from this importer.
  const Known known[] = {{"models/RiggedSimple/RiggedSimple.gltf", 96, 96, 188, 2, 1},
                         {"models/SimpleSkin/SimpleSkin.gltf", 10, 10, 8, 2, 1},
                         {"models/RiggedFigure/RiggedFigure.glb", 370, 130, 256, 19, 1},
                         {"models/CesiumMan/CesiumMan.glb", 3273, 2338, 4672, 19, 1},
                         {"models/Fox/Fox.glb", 1728, 1728, 576, 24, 3}};
  for (const auto& k : known) {
    SCOPED_TRACE(k.file);
    const Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/" + k.file);
    const ModelStats s = compute_stats(model);
    EXPECT_EQ(s.gltf_vertices, k.vertices);
    if (std::string(k.file).find("Fox") == std::string::npos) {
      EXPECT_EQ(s.welded_vertices, k.welded);
    }
    EXPECT_EQ(s.triangles, k.triangles);
    EXPECT_EQ(s.joints, k.joints);
    EXPECT_EQ(s.animations, k.animations);
    EXPECT_TRUE(find_problems(model).empty());
  }
}

TEST(GltfTest, import_without_weld_keeps_every_referenced_gltf_vertex_in_order_of_first_use) {
  const std::string fox = std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb";
  ImportOptions apart;
  apart.weld = false;
  const Model welded = read_gltf(fox), split = read_gltf(fox, apart);
  ASSERT_EQ(split.meshes.size(), welded.meshes.size());
  const Primitive& a = welded.meshes[0].primitives[0];
  const Primitive& b = split.meshes[0].primitives[0];
  // Fox is non-indexed: glTF vertex i is corner i, so vertex i of the unwelded mesh is glTF vertex i.
  EXPECT_EQ(b.mesh.vertex_count(), b.gltf_vertices);
  EXPECT_EQ(b.welded_merged, 0u);
  EXPECT_EQ(a.welded_merged, a.gltf_vertices - a.mesh.vertex_count());
  ASSERT_EQ(b.mesh.face_count(), a.mesh.face_count());
  for (std::uint32_t f = 0; f < b.mesh.face_count(); ++f) {
    const Triangle& t = b.mesh.face(FaceId(f));
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(t[k].index, 3 * f + std::uint32_t(k));
      EXPECT_EQ(b.mesh.position(t[k]), a.mesh.position(a.mesh.face(FaceId(f))[k]));
    }
  }
}

TEST(GltfTest, a_file_reads_as_its_bytes_do_into_arrays_with_the_room_operations_get) {
  auto read_bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const std::string cesium = std::string(DEEPCUT_ASSETS_DIR) + "/models/CesiumMan/CesiumMan.glb";
  const std::vector<unsigned char> bytes = read_bytes(cesium);
  Model from_file = read_gltf(cesium);  // the file mapped, where the system allows it
  const Model from_memory = read_gltf_memory(bytes, "CesiumMan.glb");
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "deepcut_gltf_mapped";
  std::filesystem::create_directories(dir);
  write_gltf(from_file, (dir / "file.glb").string());
  write_gltf(from_memory, (dir / "memory.glb").string());
  EXPECT_EQ(read_bytes((dir / "file.glb").string()), read_bytes((dir / "memory.glb").string()));
  std::filesystem::remove_all(dir);
  // The weld renumbers the faces in the array the reader made with room: reserving room for
  // operations afterwards moves no face.
  SurfaceMesh& mesh = from_file.meshes[0].primitives[0].mesh;
  EXPECT_GE(mesh.faces().capacity(), operation_face_room(mesh.face_slots()));
  const Triangle* faces = mesh.faces().data();
  reserve_for_operations(from_file);
  EXPECT_EQ(mesh.faces().data(), faces);
}

TEST(GltfTest, fox_is_non_indexed_and_welds_to_a_closed_surface) {
  const Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb");
  const ModelStats s = compute_stats(model);
  EXPECT_LT(s.welded_vertices, 1728u / 3);  // non-indexed: every corner its own glTF vertex
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(model.animations.size(), 3u);
  EXPECT_EQ(model.animations[1].name, "Walk");
  ASSERT_EQ(model.images.size(), 1u);
  EXPECT_EQ(model.images[0].mime_type, "image/png");
}

TEST(GltfTest, strides_normalised_ints_sparse_and_skin_without_inverse_bind_matrices) {
  std::vector<unsigned char> buf;
  const json doc = quirky_gltf(buf);
  const std::string dir = test::temp_dir("quirky");
  const std::string path = write_text(dir, "quirky.gltf", doc.dump());
  const Model model = read_gltf(path);
  ASSERT_EQ(model.skins.size(), 1u);
  EXPECT_FALSE(model.skins[0].had_inverse_bind_matrices);
  EXPECT_EQ(model.skins[0].inverse_bind_matrices[1], glm::mat4(1.0f));
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  ASSERT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(mesh.positions()[3], glm::vec3(0, 2, 0));  // sparse override
  const auto& uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
  EXPECT_FLOAT_EQ(uv[1].x, 1.0f);  // corner 1 of face 0 is vertex 1: u = 65535/65535
  const auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  EXPECT_FLOAT_EQ(w[0].x, 0.5f);  // 100/255 + 100/255 normalised to 0.5 + 0.5
  EXPECT_FLOAT_EQ(w[0].y, 0.5f);
  bool noted = false;
  for (const auto& p : model.import_problems) noted |= p.message.find("not summing to 1") != std::string::npos;
  EXPECT_TRUE(noted);
  ASSERT_EQ(model.materials.size(), 1u);
  EXPECT_NE(model.materials[0].json.find("emissiveStrength"), std::string::npos);

  // Export writes inverseBindMatrices, keeps the extension, and the validator accepts it.
  const std::string out = dir + "/quirky-out.glb";
  write_gltf(model, out);
  const auto v = test::validate_gltf(out);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const Model again = read_gltf(out);
  EXPECT_TRUE(again.skins[0].had_inverse_bind_matrices);
  EXPECT_EQ(again.extensions_used, model.extensions_used);
  EXPECT_EQ(again.meshes[0].primitives[0].mesh.positions(), mesh.positions());
  std::filesystem::remove_all(dir);
}

TEST(GltfTest, skin_joints_read_in_place_sanitise_as_the_decoded_ones_do) {
  // More than one chunk of vertices (32768), runs of repeated bad influences crossing its edge;
  // 32-bit joints take the decode, an independent reference for bytes and shorts read in place.
  const std::string dir = test::temp_dir("joint-types");
  const std::size_t nv = 3 * 13000;
  ImportOptions apart;
  apart.weld = false;
  std::size_t kinds[7];
  auto read = [&](const std::string& name, int joint_type, bool interleaved) {
    const json doc = run_skinned_gltf(dir, name, nv, joint_type, interleaved, kinds);
    return read_gltf(write_text(dir, name + ".gltf", doc.dump()), apart);
  };
  const Model reference = read("u32", 5125, false);
  const SurfaceMesh& ref = reference.meshes[0].primitives[0].mesh;
  ASSERT_EQ(ref.vertex_count(), nv);
  auto count = [&](const Model& m, const std::string& kind) {
    std::size_t n = 0;
    for (const ImportProblem& p : m.import_problems) n += p.kind == kind ? p.count : 0;
    return n;
  };
  // Each kind of bad influence, repaired once per vertex that has it.
  EXPECT_EQ(count(reference, "weights-invalid"), kinds[1] + kinds[2]);
  EXPECT_EQ(count(reference, "joints-past-skin"), kinds[3]);
  EXPECT_EQ(count(reference, "influences-duplicate-joint"), kinds[4]);
  EXPECT_EQ(count(reference, "weights-zero"), kinds[5]);
  EXPECT_EQ(count(reference, "weights-normalised"), kinds[3] + kinds[6]);
  const auto& ref_joints = ref.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
  const auto& ref_weights = ref.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  const std::tuple<const char*, int, bool> variants[] = {
      {"u16", 5123, false}, {"u16-interleaved", 5123, true}, {"u8", 5121, false}};
  for (const auto& [name, type, interleaved] : variants) {
    SCOPED_TRACE(name);
    const Model m = read(name, type, interleaved);
    const SurfaceMesh& mesh = m.meshes[0].primitives[0].mesh;
    ASSERT_EQ(mesh.vertex_count(), nv);
    const auto& joints = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
    const auto& weights = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
    std::size_t differ = 0;
    for (std::size_t v = 0; v < nv; ++v)
      differ +=
          joints[v] != ref_joints[v] || std::memcmp(&weights[v], &ref_weights[v], sizeof(glm::vec4)) != 0;
    EXPECT_EQ(differ, 0u);
    ASSERT_EQ(m.import_problems.size(), reference.import_problems.size());
    for (std::size_t i = 0; i < m.import_problems.size(); ++i) {
      EXPECT_EQ(m.import_problems[i].kind, reference.import_problems[i].kind);
      EXPECT_EQ(m.import_problems[i].count, reference.import_problems[i].count) << m.import_problems[i].kind;
      EXPECT_EQ(m.import_problems[i].message, reference.import_problems[i].message);
      EXPECT_EQ(m.import_problems[i].places, reference.import_problems[i].places);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(GltfTest, external_buffer_uris_must_stay_in_the_models_folder) {
  std::vector<unsigned char> buf;
  json doc = quirky_gltf(buf);
  const std::string dir = test::temp_dir("escape");
  std::filesystem::create_directories(dir + "/model");
  std::ofstream(dir + "/secret.bin", std::ios::binary).write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size()));
  doc["buffers"][0]["uri"] = "../secret.bin";
  const std::string bad = write_text(dir + "/model", "escape.gltf", doc.dump());
  try {
    read_gltf(bad);
    FAIL() << "a buffer outside the model's folder was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("outside the model's folder"), std::string::npos) << e.what();
  }
  // The same file next to the model is fine.
  std::filesystem::copy_file(dir + "/secret.bin", dir + "/model/data.bin");
  doc["buffers"][0]["uri"] = "data.bin";
  EXPECT_NO_THROW(read_gltf(write_text(dir + "/model", "ok.gltf", doc.dump())));
  std::filesystem::remove_all(dir);
}

TEST(GltfTest, strips_and_fans_become_triangles) {
  std::vector<unsigned char> buf;
  json doc = quirky_gltf(buf);
  const std::string dir = test::temp_dir("modes");
  doc["meshes"][0]["primitives"][0]["mode"] = 6;  // fan over 0 1 2 0 2 3: 4 triangles
  const Model fan = read_gltf(write_text(dir, "fan.gltf", doc.dump()));
  EXPECT_EQ(fan.meshes[0].primitives[0].mesh.face_count(), 4u);
  doc["meshes"][0]["primitives"][0]["mode"] = 1;  // lines: rejected clearly
  try {
    read_gltf(write_text(dir, "lines.gltf", doc.dump()));
    FAIL() << "lines were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("LINES"), std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST(GltfTest, write_is_atomic_and_rejects_unknown_extensions) {
  const Model model = test::make_skinned_tube_model();
  const std::string dir = test::temp_dir("atomic");
  EXPECT_THROW(write_gltf(model, dir + "/x.obj"), Error);
  EXPECT_THROW(write_gltf(model, dir + "/missing-folder/x.glb"), Error);
  write_gltf(model, dir + "/tube.glb");
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);  // no temporary left behind
  const auto v = test::validate_gltf(dir + "/tube.glb");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  std::filesystem::remove_all(dir);
}

// Export, import, export again: the same bytes, for every bundled model as read and after a
// cut and a drill (new vertices, blended weights and normals). Normalising normals, rotations
// and weights must be idempotent, or a CLI chain through files drifts in the last bits.
TEST(GltfTest, an_export_reexports_to_the_same_bytes) {
  const std::string dir = test::temp_dir("reexport");
  auto bytes_of = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const std::string& path : test::asset_models()) {
    SCOPED_TRACE(path);
    Model model = read_gltf(path);
    BoundingBox box;
    for (const auto& mesh : model.meshes)
      for (const auto& prim : mesh.primitives) box.add(prim.mesh.bounds());
    for (int stage = 0; stage < 3; ++stage) {
      if (stage == 1) cut_model(model, Plane{0.5f * (box.min + box.max), glm::vec3(0.3f, 1.0f, 0.2f)});
      if (stage == 2) {
        const glm::vec3 c = 0.5f * (box.min + box.max), d(0.0f, 0.0f, box.diagonal());
        drill_model(model, Cylinder{c - d, c + d, 0.05f * box.diagonal()});
      }
      write_gltf(model, dir + "/first.glb");
      write_gltf(read_gltf(dir + "/first.glb"), dir + "/second.glb");
      const std::string first = bytes_of(dir + "/first.glb"), second = bytes_of(dir + "/second.glb");
      ASSERT_FALSE(first.empty());
      EXPECT_TRUE(first == second) << "stage " << stage << " (0: as read, 1: cut, 2: drilled) re-exports differently";
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(GltfTest, brainstem_local_only_model_loads_when_present) {
  const std::string path = std::string(DEEPCUT_SHARED_MODELS_DIR) + "/local-only/BrainStem/BrainStem.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "local-only models are not on this machine";
  const Model model = read_gltf(path);
  const ModelStats s = compute_stats(model);
  EXPECT_EQ(s.primitives, 59u);
  EXPECT_EQ(s.gltf_vertices, 34159u);
  EXPECT_EQ(s.triangles, 61666u);
  EXPECT_EQ(s.nonmanifold_edges, 72u);
  const std::string dir = test::temp_dir("brainstem");
  write_gltf(model, dir + "/b.glb");
  const auto v = test::validate_gltf(dir + "/b.glb");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const Model again = read_gltf(dir + "/b.glb");
  const ModelStats s2 = compute_stats(again);
  EXPECT_EQ(s2.triangles, s.triangles);
  EXPECT_EQ(s2.welded_vertices, s.welded_vertices);
  EXPECT_EQ(s2.nonmanifold_edges, s.nonmanifold_edges);
  std::filesystem::remove_all(dir);
}

}  // namespace deepcut
