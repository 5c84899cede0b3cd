// SPDX-License-Identifier: MIT
// The bad-input catalogue (tests/data/bad/, made by scripts/make_bad_inputs.py) through the
// command line as a user runs it, under a memory limit and a timeout. The table says, per file,
// what `deepcut info` and `deepcut convert` must do: refuse it (exit 2, exactly one stderr line
// naming the file and the problem, nothing written) or handle it (exit 0, the problem listed in
// `info --json` "problems" under its kind, every repair or loss of reading also on convert's
// stderr (one line per kind, naming the file) and in its `--json` "problems", an export that
// passes the Khronos validator and reads back).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/validate.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::string kBadDir = std::string(DEEPCUT_SOURCE_DIR) + "/tests/data/bad";

enum class Outcome { Refused, Handled };

struct Expectation {
  const char* file;  // relative to tests/data/bad
  Outcome outcome;
  // Refused: words the one stderr line must contain. Handled: words one of the "problems" must
  // contain ("" means the file is clean: no problems at all).
  const char* words;
  // Handled: the problem's kind, and whether reading repaired or dropped it (then every command
  // names it on stderr) rather than `info` finding it in the mesh.
  const char* kind = "";
  bool read_repair = false;
};

constexpr Outcome kRefused = Outcome::Refused;
constexpr Outcome kHandled = Outcome::Handled;

const Expectation kCatalogue[] = {
    // containers
    {"control_simple_skin.glb", kHandled, ""},
    {"glb_empty.glb", kRefused, "file is empty"},
    {"glb_truncated.glb", kRefused, "truncated .glb: header says 50116 bytes, file has 30069"},
    {"glb_truncated_header.glb", kRefused, "truncated .glb"},
    {"glb_wrong_magic.glb", kRefused, "does not start with the magic 'glTF'"},
    {"glb_version_1.glb", kRefused, ".glb version 1 is not supported"},
    {"glb_length_past_end.glb", kRefused, "truncated .glb: header says 1048576 bytes"},
    {"glb_json_chunk_past_end.glb", kRefused, "JSON chunk length runs past the end"},
    {"glb_bin_chunk_past_end.glb", kRefused, "BIN chunk length runs past the end"},
    {"glb_first_chunk_not_json.glb", kRefused, "first chunk is not JSON"},
    {"glb_buffer_longer_than_bin.glb", kRefused, "byteLength"},
    // JSON
    {"json_syntax_error.gltf", kRefused, "invalid JSON"},
    {"json_not_object.gltf", kRefused, "top level is not a JSON object"},
    {"json_no_asset.gltf", kRefused, "'asset' is missing"},
    {"json_version_1.gltf", kRefused, "version '1.0' is not supported"},
    {"json_deep_nesting.gltf", kRefused, "more than 512 levels deep"},
    {"json_random_bytes.gltf", kRefused, "invalid JSON"},
    {"json_wrong_types.gltf", kRefused, "'accessors' is not an array"},
    {"not_a_model.txt", kRefused, "not a model file (this build reads"},
    // accessors, buffer views, buffers
    {"accessor_missing.gltf", kRefused, "accessor out of bounds"},
    {"accessor_past_buffer_view.gltf", kRefused,
     "100000 elements of 2 bytes at offset 0 run past the end of bufferView 0"},
    {"accessor_offset_overflow.gltf", kRefused,
     "at offset 18446744073709551516 run past the end of bufferView 1"},
    {"accessor_stride_too_small.gltf", kRefused, "byteStride 4 is smaller than an element"},
    {"accessor_bad_component_type.gltf", kRefused, "unknown componentType 5130"},
    {"accessor_sparse_index_out_of_range.gltf", kRefused, "sparse index 1000 is out of range"},
    {"accessor_reused_amplification.gltf", kRefused, "claims far more data than it holds"},
    {"buffer_view_missing.gltf", kRefused, "bufferView 99 does not exist"},
    {"buffer_view_past_buffer.gltf", kRefused, "bufferView 1 runs past the end of its buffer"},
    {"buffer_missing.gltf", kRefused, "buffer 9 does not exist"},
    {"buffer_bad_base64.gltf", kRefused, "not valid base64"},
    {"buffer_length_mismatch.gltf", kRefused, "claims 1000000000 bytes, its data URI holds 168"},
    {"index_past_vertex_count.gltf", kRefused, "index 65000 (position 5) is past the 10 vertices"},
    {"index_count_not_multiple_of_3.gltf", kRefused, "index count 23 is not a multiple of 3"},
    {"triangles_10m_claim.gltf", kRefused,
     "30000000 elements of 2 bytes at offset 0 run past the end of bufferView 0"},
    {"triangles_10m_sparse_claim.gltf", kRefused, "claims far more data than it holds"},
    {"primitive_lines.gltf", kRefused, "only triangle primitives are supported"},
    {"primitive_no_position.gltf", kRefused, "has no POSITION attribute"},
    {"attribute_bad_texcoord_name.gltf", kHandled, "1 attribute dropped (not a valid glTF attribute name): TEXCOORD_x",
     "attribute-invalid-name-dropped", true},
    // geometry
    {"position_nan.gltf", kRefused, "POSITION 3 is not finite"},
    {"position_inf.gltf", kRefused, "POSITION 7 is not finite"},
    {"zero_vertex_mesh.gltf", kHandled, "has no triangles (left out on export)", "no-triangles"},
    {"triangles_zero_area.gltf", kHandled, "2 degenerate triangles", "degenerate-triangles"},
    {"triangles_duplicate.gltf", kHandled, "2 duplicate triangles", "duplicate-triangles"},
    {"nonmanifold_vertex.gltf", kHandled, "1 non-manifold vertex", "nonmanifold-vertices"},
    {"edge_with_three_faces.gltf", kHandled, "1 non-manifold edge", "nonmanifold-edges"},
    {"normals_inverted.gltf", kHandled,
     "188 triangles have normals pointing against their winding (inverted normals): mesh 0 'Cylinder' primitive 0 "
     "(188 of 188)",
     "inverted-normals"},
    // skins and animation
    {"weights_sum_zero.gltf", kHandled, "4 vertices had no weight", "weights-zero", true},
    {"weights_sum_seven.gltf", kHandled, "10 vertices had weights not summing to 1 (normalised)", "weights-normalised", true},
    {"weights_sum_098.gltf", kHandled, "10 vertices had weights not summing to 1 (normalised)", "weights-normalised", true},
    {"weights_negative_nan.gltf", kHandled, "2 weights were negative or NaN (set to 0)", "weights-invalid", true},
    {"joint_past_skin.gltf", kHandled, "4 influences named a joint past the skin (dropped)", "joints-past-skin", true},
    {"joints_repeated_in_vertex.gltf", kHandled, "2 influences named a joint their vertex already had (weights summed)",
     "influences-duplicate-joint", true},
    {"skin_without_inverse_bind_matrices.gltf", kHandled, "1 skin has no inverseBindMatrices (identity matrices used",
     "skin-no-inverse-bind-matrices", true},
    {"skin_ibm_last_row_noise.gltf", kHandled,
     "2 inverse bind matrices were not exactly affine (last row snapped to 0, 0, 0, 1): skin 0", "ibm-snapped", true},
    {"skin_ibm_not_affine.gltf", kRefused, "skin 0: inverse bind matrix 1 is not affine"},
    {"skin_joint_listed_twice.gltf", kHandled,
     "1 joint listed twice in its skin merged (JOINTS remapped to its first listing): skin 0", "skin-duplicate-joints", true},
    {"skin_joint_listed_twice_other_ibm.gltf", kHandled,
     "1 joint listed twice in its skin with another inverse bind matrix now lists a new child node of the joint",
     "skin-duplicate-joints-stand-in", true},
    {"skin_too_few_inverse_bind_matrices.gltf", kRefused, "fewer inverseBindMatrices than joints"},
    {"skin_inverse_bind_matrix_nan.gltf", kRefused, "inverse bind matrix 1 is not finite"},
    {"skin_joint_missing_node.gltf", kRefused, "joint node 40, which does not exist"},
    {"node_cycle.gltf", kRefused, "cycle"},
    {"animation_times_decreasing.gltf", kRefused, "key times are not increasing"},
    {"animation_quaternion_not_unit.gltf", kHandled, "12 rotations were not unit quaternions (normalised)",
     "rotations-normalised", true},
    // what the file carries
    {"extras_and_extensions.gltf", kHandled, "1 extension dropped (not carried through on that object): EXT_deepcut_mesh_test",
     "extension-dropped", true},
    // images
    {"control_textured.gltf", kHandled, ""},
    {"image_huge_claim.gltf", kRefused, "claims 1000000 x 1000000 pixels, over the 32768-pixel limit"},
    {"image_view_past_buffer.gltf", kRefused, "runs past the end of its buffer"},
    {"image_uri_escapes.gltf", kRefused, "points outside the model's folder (refused, not read)"},
    // URIs
    {"uri_escapes_etc_passwd.gltf", kRefused,
     "'../../etc/passwd' points outside the model's folder (refused, not read)"},
    {"uri_absolute.gltf", kRefused, "'/etc/passwd' is an absolute path, outside the model's folder"},
    {"uri_percent_encoded.gltf", kRefused, "points outside the model's folder (refused, not read)"},
    {"uri_missing_file.gltf", kRefused, "missing.bin"},
    {"escape/uri_to_parent_folder.gltf", kRefused,
     "'../escape_target.bin' points outside the model's folder"},
    // compressed: KHR_draco_mesh_compression, EXT_meshopt_compression
    {"draco_truncated.glb", kRefused, "the Draco data could not be decoded"},
    {"draco_not_draco.glb", kRefused, "not Draco data"},
    {"draco_count_mismatch.glb", kRefused, "Draco decodes 3572 vertices, accessor 3 says 3000"},
    {"draco_attribute_id_missing.glb", kRefused, "the Draco data has no attribute with id 9"},
    {"meshopt_count_overflow.glb", kRefused, "count 4294967295 is implausibly large"},
    {"meshopt_bad_filter.glb", kRefused, "filter OCTAHEDRAL needs byteStride 4 or 8, not 12"},
    {"meshopt_unknown_filter.glb", kRefused, "unknown filter 'ZIGZAG'"},
    {"meshopt_stride_mismatch.glb", kRefused, "count 1728 x byteStride 8 = 13824 bytes, but the bufferView is 6912 bytes long"},
    {"meshopt_truncated.glb", kRefused, "the ATTRIBUTES data could not be decoded"},
    {"meshopt_past_buffer.glb", kRefused, "run past the end of buffer 0"},
    {"meshopt_bad_mode.glb", kRefused, "mode 'LINES' is not ATTRIBUTES, TRIANGLES or INDICES"},
    // static meshes (plugins/static_formats)
    {"static/control_cube.off", kHandled, "6 polygons split into triangle fans", "polygons-triangulated", true},
    {"static/control_cube_ascii.stl", kHandled, ""},
    {"static/obj_empty.obj", kRefused, "file is empty"},
    {"static/obj_truncated.obj", kRefused, "no faces (only 2204 points)"},
    {"static/obj_index_out_of_range.obj", kRefused, "line 14: '99' is not one of the 8 vertices defined before it"},
    {"static/obj_nan.obj", kRefused, "line 2: 'nan' is not a finite number"},
    {"static/obj_binary_garbage.obj", kRefused, "Line longer than"},
    {"static/obj_unreferenced_vertices.obj", kHandled, "3 unreferenced vertices dropped", "unreferenced-vertices-dropped", true},
    {"static/obj_uv_index_out_of_range.obj", kRefused, "line 187: '5454' is not one of the 71 texture coordinates"},
    {"static/off_truncated.off", kRefused, "truncated: the header claims 6 faces, the file holds 4"},
    {"static/off_huge_counts.off", kRefused, "the header claims 100000000 vertices; the file is only 38 bytes"},
    {"static/off_index_out_of_range.off", kRefused, "face 5 uses vertex 8, past the 8 vertices"},
    {"static/off_negative_index.off", kRefused, "face 5 uses vertex -1"},
    {"static/off_nan.off", kRefused, "vertex 1 is not finite"},
    {"static/off_no_faces.off", kRefused, "no faces (only 8 points)"},
    {"static/ply_truncated.ply", kRefused, "truncated PLY: face 4 of 6 is missing or incomplete"},
    {"static/ply_huge_count.ply", kRefused, "claims 100000000 vertex elements"},
    {"static/ply_index_out_of_range.ply", kRefused, "face 5 uses vertex 1000, past the 8 vertices"},
    {"static/ply_no_end_header.ply", kRefused, "no 'end_header' line"},
    {"static/ply_index_huge.ply", kRefused, "face 2 uses vertex 65536, past the 8 vertices"},
    {"static/stl_empty.stl", kRefused, "file is empty"},
    {"static/stl_truncated.stl", kRefused, "truncated binary STL: the header says 12 triangles, the file holds 4"},
    {"static/stl_huge_count.stl", kRefused, "the header says 10000000 triangles"},
    {"static/stl_nan.stl", kRefused, "is not finite"},
    {"static/stl_solid_with_control_bytes.stl", kRefused, "truncated binary STL: the header says"},
};

// Test names print the file, not the bytes of the struct.
void PrintTo(const Expectation& e, std::ostream* os) { *os << e.file; }

std::size_t line_count(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

// `deepcut ARGS` under a 2 GiB memory limit and a timeout. ASan reserves terabytes of address
// space, so a sanitizer build limits the resident size through ASan instead of `ulimit -v`.
test::RunResult run_limited(const std::string& args) {
  const std::string limit = kSanitized
                                ? "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=2048\" "
                                : "ulimit -v 2097152; ";
  const std::string timeout = kSanitized ? "timeout 300 " : "timeout 60 ";
  return test::run_command(limit + timeout + test::quote(DEEPCUT_CLI) + " " + args);
}

std::string case_name(const ::testing::TestParamInfo<Expectation>& info) {
  std::string name = info.param.file;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// `convert --json` names each repair or loss of reading twice: one stderr line per kind
// ("deepcut: FILE: MESSAGE [KIND]") and one entry of "problems"; a read repair the table expects
// is among them, and a clean file has none.
void expect_read_problems_reported(const test::RunResult& convert, const std::string& path, const Expectation& e) {
  const json problems = json::parse(convert.out).at("problems");
  EXPECT_EQ(line_count(convert.err), problems.size()) << convert.err << problems.dump();
  for (const auto& p : problems) {
    const std::string line = "deepcut: " + path + ": " + p.at("message").get<std::string>() + " [" +
                             p.at("kind").get<std::string>() + "]\n";
    EXPECT_NE(convert.err.find(line), std::string::npos) << "missing stderr line " << line << convert.err;
  }
  const bool listed = std::any_of(problems.begin(), problems.end(), [&](const json& p) { return p.at("kind") == e.kind; });
  EXPECT_EQ(listed, e.read_repair) << e.kind << " on convert: " << problems.dump();
  if (std::string(e.words).empty()) {
    EXPECT_TRUE(problems.empty()) << problems.dump();
  }
}

class BadInputTest : public ::testing::TestWithParam<Expectation> {
 protected:
  void SetUp() override { dir_ = test::temp_dir("bad"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

}  // namespace

TEST_P(BadInputTest, info_and_convert_refuse_or_handle_it) {
  Expectation e = GetParam();
  // A build without the static formats plugin (DEEPCUT_BUILD_VTK=OFF, e.g. the quick sanitizer
  // run) refuses every static file, good or bad, saying it cannot read that kind of file.
  std::string unreadable;
  if (!DEEPCUT_HAVE_STATIC_FORMATS && std::string(e.file).rfind("static/", 0) == 0) {
    unreadable = "cannot read ." + fs::path(e.file).extension().string().substr(1) + " files";
    e = {e.file, kRefused, unreadable.c_str()};
  }
  const std::string path = kBadDir + "/" + e.file;
  ASSERT_TRUE(fs::exists(path)) << "missing from the catalogue; run python3 scripts/make_bad_inputs.py";
  const std::string name = fs::path(e.file).filename().string();
  const std::string out = dir_ + "/out.glb";
  const auto info = run_limited("info --json " + test::quote(path));
  const auto convert = run_limited("convert --json " + test::quote(path) + " -o " + test::quote(out));

  if (e.outcome == Outcome::Refused) {
    for (const auto* r : {&info, &convert}) {
      EXPECT_EQ(r->exit_code, 2) << r->err;
      EXPECT_EQ(line_count(r->err), 1u) << "exactly one stderr line: " << r->err;
      EXPECT_NE(r->err.find(name), std::string::npos) << "the line should name the file: " << r->err;
      EXPECT_NE(r->err.find(e.words), std::string::npos)
          << "the line should say '" << e.words << "': " << r->err;
      EXPECT_TRUE(r->out.empty()) << "nothing on stdout: " << r->out;
    }
    EXPECT_FALSE(fs::exists(out)) << "nothing may be written on failure";
    return;
  }

  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_TRUE(info.err.empty()) << info.err;
  const json j = json::parse(info.out);
  const json& problems = j.at("problems");
  if (std::string(e.words).empty()) {
    EXPECT_TRUE(problems.empty()) << problems.dump();
  } else {
    EXPECT_TRUE(std::any_of(problems.begin(), problems.end(), [&](const json& p) {
      return p.at("kind") == e.kind && p.at("message").get<std::string>().find(e.words) != std::string::npos;
    })) << "problems should hold " << e.kind << " saying '" << e.words << "': " << problems.dump();
  }

  ASSERT_EQ(convert.exit_code, 0) << convert.err;
  expect_read_problems_reported(convert, path, e);
  const auto v = test::validate_gltf(out);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const Model back = read_gltf(out);
  EXPECT_EQ(compute_stats(back).triangles, j["triangles"].get<std::size_t>());
  for (const auto& mesh : back.meshes)
    for (const auto& prim : mesh.primitives) EXPECT_NO_THROW(validate_mesh(prim.mesh));
}

INSTANTIATE_TEST_SUITE_P(Catalogue, BadInputTest, ::testing::ValuesIn(kCatalogue), case_name);

TEST(BadInputCatalogue, every_file_has_an_expectation_and_every_expectation_a_file) {
  std::set<std::string> listed, found;
  for (const auto& e : kCatalogue) EXPECT_TRUE(listed.insert(e.file).second) << "listed twice: " << e.file;
  for (const auto& entry : fs::recursive_directory_iterator(kBadDir)) {
    if (!entry.is_regular_file()) continue;
    const std::string rel = fs::relative(entry.path(), kBadDir).generic_string();
    const std::string ext = entry.path().extension().string();
    for (const char* model : {".gltf", ".glb", ".obj", ".ply", ".stl", ".off", ".txt"})
      if (ext == model) found.insert(rel);
  }
  for (const auto& f : found) EXPECT_TRUE(listed.count(f)) << f << " has no row in kCatalogue";
  for (const auto& f : listed) EXPECT_TRUE(found.count(f)) << f << " is listed but not in " << kBadDir;
  EXPECT_GE(found.size(), 80u);
}

TEST(BadInputCatalogue, matches_its_generator) {
  const auto r = test::run_command(
      "python3 " + test::quote(std::string(DEEPCUT_SOURCE_DIR) + "/scripts/make_bad_inputs.py") + " --check");
  EXPECT_EQ(r.exit_code, 0) << "tests/data/bad differs from scripts/make_bad_inputs.py; rerun it:\n" << r.err;
}

class HostileFileSystemTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("hostile-fs"); }
  void TearDown() override { fs::remove_all(dir_); }

  // SimpleSkin with buffer 0 moved out to the external file `uri`, inside `folder`.
  std::string write_model(const std::string& folder, const std::string& uri) {
    std::ifstream in(std::string(DEEPCUT_ASSETS_DIR) + "/models/SimpleSkin/SimpleSkin.gltf");
    json doc = json::parse(in);
    doc["buffers"][0]["uri"] = uri;
    fs::create_directories(folder);
    const std::string path = folder + "/model.gltf";
    std::ofstream(path) << doc.dump();
    return path;
  }
  std::string dir_;
};

TEST_F(HostileFileSystemTest, a_symlink_out_of_the_folder_is_refused_and_not_read) {
  // escape_target.bin is SimpleSkin's buffer 0, a perfectly valid buffer: a load through the
  // link that succeeded would prove the file outside the folder was read.
  const std::string outside = kBadDir + "/escape_target.bin";
  const std::string good = write_model(dir_ + "/good", "buffer.bin");
  fs::copy_file(outside, dir_ + "/good/buffer.bin");
  const auto control = run_limited("info " + test::quote(good));
  EXPECT_EQ(control.exit_code, 0) << "the same buffer inside the folder must load: " << control.err;

  const std::string linked = write_model(dir_ + "/linked", "buffer.bin");
  fs::create_symlink(outside, dir_ + "/linked/buffer.bin");
  const auto r = run_limited("info " + test::quote(linked));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("outside the model's folder"), std::string::npos) << r.err;
}

TEST_F(HostileFileSystemTest, a_file_name_with_a_newline_still_gives_one_line) {
  const std::string path = dir_ + "/two\nlines.gltf";
  fs::copy_file(kBadDir + "/position_nan.gltf", path);
  for (const std::string& cmd : {"info " + test::quote(path),
                                 "convert " + test::quote(path) + " -o " + test::quote(dir_ + "/o.glb")}) {
    const auto r = run_limited(cmd);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("two lines.gltf"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("is not finite"), std::string::npos) << r.err;
  }
}

TEST_F(HostileFileSystemTest, a_fifo_is_refused_instead_of_blocking) {
  // Reading a FIFO with no writer would block forever; the timeout in run_limited turns a hang
  // into exit code 124.
  const std::string fifo = dir_ + "/model/buffer.bin";
  const std::string model_path = write_model(dir_ + "/model", "buffer.bin");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto r = run_limited("info " + test::quote(model_path));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is not a regular file"), std::string::npos) << r.err;

  const std::string fifo_model = dir_ + "/model/fifo.glb";
  ASSERT_EQ(::mkfifo(fifo_model.c_str(), 0600), 0);
  r = run_limited("info " + test::quote(fifo_model));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("is not a regular file"), std::string::npos) << r.err;
}

}  // namespace deepcut
