// SPDX-License-Identifier: MIT
// Static mesh formats (plugins/static_formats): OBJ, PLY and STL through VTK's readers, OFF
// through parse_off. Small files are written here, so every expectation follows from the bytes;
// each load must give a valid unrigged model (one root joint, weights 1 on joint 0) whose export
// passes the Khronos validator, and every malformed file one Error naming the file.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/validate.h"
#include "deepcut/plugins/formats.h"
#include "deepcut/plugins/static_formats.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

namespace fs = std::filesystem;

class StaticFormatsTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("static-formats"); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  std::string dir_;
};

// The unit cube's 8 corners; faces as quads, outward.
const char* kCubeCorners =
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";
const int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

std::string cube_off(const std::string& header = "OFF") {
  std::string s = header + "\n# a comment line\n8 6 12\n" + kCubeCorners;
  for (const auto& q : kCubeQuads)
    s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
         std::to_string(q[3]) + "\n";
  return s;
}

// A cube whose every face has its own UV square and normal: 24 OBJ corners over 8 positions.
std::string cube_obj() {
  std::string s = "# cube\nmtllib missing.mtl\n";
  std::istringstream corners(kCubeCorners);
  float x, y, z;
  while (corners >> x >> y >> z) s += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  s += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  s += "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn 1 0 0\nvn -1 0 0\n";
  for (int f = 0; f < 6; ++f) {
    s += "f";
    for (int k = 0; k < 4; ++k)
      s += " " + std::to_string(kCubeQuads[f][k] + 1) + "/" + std::to_string(k + 1) + "/" + std::to_string(f + 1);
    s += "\n";
  }
  return s;
}

std::string cube_ply_ascii() {
  std::string s =
      "ply\nformat ascii 1.0\ncomment cube\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 6\n"
      "property list uchar int vertex_indices\nend_header\n";
  std::istringstream corners(kCubeCorners);
  float x, y, z;
  int i = 0;
  while (corners >> x >> y >> z) {
    s += std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " " + std::to_string(30 * i) + " 255 0\n";
    ++i;
  }
  for (const auto& q : kCubeQuads)
    s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
         std::to_string(q[3]) + "\n";
  return s;
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}
void put_f32(std::string& s, float f) {
  std::uint32_t v;
  std::memcpy(&v, &f, 4);
  put_u32(s, v);
}

std::string cube_ply_binary() {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  std::istringstream corners(kCubeCorners);
  float x, y, z;
  while (corners >> x >> y >> z) {
    put_f32(s, x);
    put_f32(s, y);
    put_f32(s, z);
  }
  for (const auto& q : kCubeQuads) {
    s += static_cast<char>(4);
    for (int k = 0; k < 4; ++k) put_u32(s, static_cast<std::uint32_t>(q[k]));
  }
  return s;
}

std::vector<std::array<glm::vec3, 3>> cube_triangles() {
  const glm::vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::vector<std::array<glm::vec3, 3>> out;
  for (const auto& q : kCubeQuads) {
    out.push_back({c[q[0]], c[q[1]], c[q[2]]});
    out.push_back({c[q[0]], c[q[2]], c[q[3]]});
  }
  return out;
}

std::string cube_stl_binary(std::uint32_t claimed = 12) {
  std::string s(80, ' ');
  put_u32(s, claimed);
  for (const auto& t : cube_triangles()) {
    for (int k = 0; k < 3; ++k) put_f32(s, 0.0f);
    for (const auto& p : t)
      for (int k = 0; k < 3; ++k) put_f32(s, p[k]);
    s += std::string(2, '\0');
  }
  return s;
}

std::string cube_stl_ascii() {
  std::string s = "solid cube\n";
  for (const auto& t : cube_triangles()) {
    s += " facet normal 0 0 0\n  outer loop\n";
    for (const auto& p : t)
      s += "   vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    s += "  endloop\n endfacet\n";
  }
  return s + "endsolid cube\n";
}

// What every loaded static model must be: one mesh node skinned to the single root joint.
void expect_unrigged_model(const Model& model) {
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.meshes[0].primitives.size(), 1u);
  ASSERT_EQ(model.skins.size(), 1u);
  ASSERT_EQ(model.skins[0].joints.size(), 1u);
  EXPECT_EQ(model.nodes.size(), 2u);
  EXPECT_EQ(model.nodes[0].mesh, 0);
  EXPECT_EQ(model.nodes[0].skin, 0);
  EXPECT_EQ(model.nodes[model.skins[0].joints[0]].mesh, -1);
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  test::expect_valid(mesh, 1);
  const auto& weights = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  const auto& joints = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    ASSERT_EQ(weights[v], glm::vec4(1, 0, 0, 0));
    ASSERT_EQ(joints[v], glm::u16vec4(0));
  }
}

// A closed cube: 8 vertices, 12 triangles, no boundary, volume 1.
void expect_closed_cube(const Model& model) {
  expect_unrigged_model(model);
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  EXPECT_EQ(mesh.vertex_count(), 8u);
  EXPECT_EQ(mesh.face_count(), 12u);
  const Adjacency adj = Adjacency::build(mesh);
  EXPECT_TRUE(adj.boundary_edges().empty());
  EXPECT_TRUE(adj.nonmanifold_edges().empty());
  EXPECT_NEAR(mesh.volume(), 1.0, 1e-6);
}

void expect_exports_cleanly(const Model& model, const std::string& out) {
  write_gltf(model, out);
  const auto v = test::validate_gltf(out);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const Model back = read_gltf(out);
  EXPECT_EQ(compute_stats(back).triangles, compute_stats(model).triangles);
  ASSERT_EQ(back.skins.size(), 1u);
  EXPECT_EQ(back.skins[0].joints.size(), 1u);
}

}  // namespace

TEST_F(StaticFormatsTest, every_format_reads_the_same_closed_cube) {
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"cube.off", cube_off()},
           {"cube.obj", cube_obj()},
           {"cube.ply", cube_ply_ascii()},
           {"cube_binary.ply", cube_ply_binary()},
           {"cube.stl", cube_stl_ascii()},
           {"cube_binary.STL", cube_stl_binary()}}) {
    SCOPED_TRACE(name);
    const std::string path = write(name, bytes);
    const Model model = plugins::read_model(path);
    expect_closed_cube(model);
    EXPECT_EQ(model.meshes[0].name, fs::path(name).stem().string());
    expect_exports_cleanly(model, dir_ + "/" + fs::path(name).stem().string() + ".glb");
  }
}

TEST_F(StaticFormatsTest, obj_seams_stay_in_the_corners) {
  const Model model = plugins::read_model(write("cube.obj", cube_obj()));
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  const auto* uv = mesh.corner_attrs().find<glm::vec2>(attr::kUv0);
  const auto* normal = mesh.corner_attrs().find<glm::vec3>(attr::kNormal);
  ASSERT_NE(uv, nullptr);
  ASSERT_NE(normal, nullptr);
  // Every corner's normal is its face's outward normal: the 24 OBJ vertices welded into 8
  // without losing the hard edges.
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const glm::vec3 n = glm::normalize(glm::cross(mesh.position(t[1]) - mesh.position(t[0]), mesh.position(t[2]) - mesh.position(t[0])));
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(glm::dot((*normal)[SurfaceMesh::corner(f, k)], n), 1.0f, 1e-5f);
      const glm::vec2 c = (*uv)[SurfaceMesh::corner(f, k)];
      EXPECT_TRUE((c.x == 0 || c.x == 1) && (c.y == 0 || c.y == 1));
    }
  });
  EXPECT_GT(compute_stats(model).seam_edges, 0u);
}

TEST_F(StaticFormatsTest, ply_colours_and_off_colours_and_normals_are_carried) {
  const Model ply = plugins::read_model(write("cube.ply", cube_ply_ascii()));
  const auto* color = ply.meshes[0].primitives[0].mesh.corner_attrs().find<glm::vec4>(attr::kColor0);
  ASSERT_NE(color, nullptr);
  for (std::size_t c = 0; c < color->size(); ++c) {
    EXPECT_FLOAT_EQ((*color)[c].g, 1.0f);
    EXPECT_FLOAT_EQ((*color)[c].a, 1.0f);
  }
  expect_exports_cleanly(ply, dir_ + "/ply.gltf");

  const std::string noff = "CNOFF\n3 1 0\n0 0 0  0 0 2  255 0 0\n1 0 0  0 0 1  0 255 0\n0 1 0  0 0 1  0 0 255\n3 0 1 2\n";
  const Model off = plugins::read_model(write("tri.off", noff));
  const SurfaceMesh& mesh = off.meshes[0].primitives[0].mesh;
  const auto* n = mesh.corner_attrs().find<glm::vec3>(attr::kNormal);
  const auto* c = mesh.corner_attrs().find<glm::vec4>(attr::kColor0);
  ASSERT_NE(n, nullptr);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ((*n)[0], glm::vec3(0, 0, 1)) << "normals are normalised";
  EXPECT_EQ((*c)[0], glm::vec4(1, 0, 0, 1));
  EXPECT_EQ((*c)[2], glm::vec4(0, 0, 1, 1));
  expect_exports_cleanly(off, dir_ + "/off.glb");
}

TEST_F(StaticFormatsTest, unreferenced_points_and_repeated_corners_are_dropped_and_noted) {
  const std::string off = "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n9 9 9\n1 1 0\n3 0 1 2\n3 1 1 4\n";
  const Model model = plugins::read_model(write("loose.off", off));
  expect_unrigged_model(model);
  EXPECT_EQ(model.meshes[0].primitives[0].mesh.vertex_count(), 3u);
  EXPECT_EQ(model.meshes[0].primitives[0].mesh.face_count(), 1u);
  std::string notes;
  for (const auto& p : model.import_problems) notes += p.message + "\n";
  EXPECT_NE(notes.find("1 face repeats a vertex"), std::string::npos) << notes;
  EXPECT_NE(notes.find("2 unreferenced vertices dropped"), std::string::npos) << notes;
}

TEST(ParseOffTest, rejects_malformed_text_with_one_message_naming_the_file) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "file is empty"},
      {"OFF\n", "no vertex and face counts"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n", "the file holds 2"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n", "claims 1 faces, the file holds 0"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "uses vertex 3, past the 3 vertices"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", "uses vertex -1"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1.5\n", "uses vertex 1.5"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "has 2 corners"},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "lists 3 of its 4 corners"},
      {"OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "'zero' is not a number"},
      {"OFF\n-3 1 0\n", "is not a whole number"},
      {"OFF\n10000000 20000000 0\n0 0 0\n", "claims 10000000 vertices; the file is only"},
      {"4OFF\n3 1 0\n", "is not supported"},
      {"\x7f" "ELF\x02\x01", "does not start with an OFF header"},
  };
  for (const auto& [text, words] : cases) {
    SCOPED_TRACE(words);
    try {
      (void)plugins::parse_off(text, "bad.off");
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("bad.off: ", 0), 0u) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  }
}

TEST_F(StaticFormatsTest, broken_files_of_every_format_are_refused_with_one_error) {
  std::string truncated_ply = cube_ply_binary();
  truncated_ply.resize(truncated_ply.size() - 30);
  std::string nan_stl = cube_stl_binary();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan_stl[84 + 12], &nan, 4);
  const std::pair<std::string, std::string> cases[] = {
      {"missing.obj", ""},  // not written
      {"empty.stl", ""},
      {"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"},
      {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"},
      {"nofaces.obj", "v 0 0 0\nv 1 0 0\n"},
      {"garbage.obj", std::string("\x00\xff\x13\x37 binary \x00 garbage", 20)},
      {"truncated.ply", truncated_ply},
      {"huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"},
      {"notply.ply", "plx\n"},
      {"huge.stl", cube_stl_binary(10000000)},
      {"nan.stl", nan_stl},
      {"short.stl", std::string(40, '\x01')},
  };
  for (const auto& [name, bytes] : cases) {
    SCOPED_TRACE(name);
    const std::string path = name == "missing.obj" ? dir_ + "/missing.obj" : write(name, bytes);
    try {
      (void)plugins::read_model(path);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_TRUE(e.is_input_error());
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

TEST(FormatRegistryTest, lists_gltf_first_and_refuses_taken_extensions) {
  const plugins::FormatRegistry& formats = plugins::builtin_formats();
  ASSERT_GE(formats.list().size(), 5u);
  EXPECT_EQ(formats.list()[0].name, "glTF");
  EXPECT_EQ(plugins::extensions(formats), ".glb .gltf .obj .ply .stl .off");
  EXPECT_NE(plugins::find_format(formats, "/a/b/Model.OBJ"), nullptr);
  EXPECT_EQ(plugins::find_format(formats, "/a.obj/model"), nullptr);
  plugins::FormatRegistry mine = formats;
  EXPECT_THROW(mine.add({"Other OBJ", {"obj"}, plugins::read_static_model}), Error);
  EXPECT_THROW(mine.add({"Dotted", {".xyz"}, plugins::read_static_model}), Error);
}

}  // namespace deepcut
