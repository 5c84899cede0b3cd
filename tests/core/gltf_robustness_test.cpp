// SPDX-License-Identifier: MIT
// The glTF reader against hostile input at the library level: read_gltf_memory agrees with
// read_gltf on the whole bad-input catalogue, every model the reader accepts holds the mesh
// invariants, and every input the fuzzer ever found (tests/fuzz/regressions/) plus the seed
// corpus (tests/fuzz/corpus/) is rejected cleanly or read into a valid model.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"

namespace deepcut {
namespace {

namespace fs = std::filesystem;

std::vector<unsigned char> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

std::vector<fs::path> files_under(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename() != "README.md") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Every primitive of an accepted model must satisfy the invariants the operations rely on.
void expect_valid_model(const Model& model) {
  std::vector<std::size_t> joints(model.meshes.size(), 0);
  for (const auto& n : model.nodes)
    if (n.mesh >= 0 && n.skin >= 0)
      joints[static_cast<std::size_t>(n.mesh)] = model.skins[n.skin].joints.size();
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    for (const auto& prim : model.meshes[m].primitives) EXPECT_NO_THROW(validate_mesh(prim.mesh, joints[m]));
  EXPECT_NO_THROW(compute_stats(model));
  EXPECT_NO_THROW(find_problems(model));
}

// Reads `bytes` from memory: either a clean Error{InvalidInput} or a valid model.
void expect_clean_outcome(const std::vector<unsigned char>& bytes, const std::string& name) {
  try {
    const Model model = read_gltf_memory(bytes, name);
    expect_valid_model(model);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidInput) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(name + ": ", 0), 0u)
        << "the message should start with the name: " << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
  }
}

const fs::path kSource = DEEPCUT_SOURCE_DIR;

}  // namespace

TEST(GltfRobustnessTest, memory_reader_agrees_with_the_file_reader_on_the_catalogue) {
  const auto files = files_under(kSource / "tests/data/bad");
  ASSERT_GE(files.size(), 60u);
  std::size_t accepted = 0, refused = 0;
  for (const auto& path : files) {
    const std::string ext = path.extension().string();
    if (ext != ".gltf" && ext != ".glb") continue;
    SCOPED_TRACE(path.string());
    const std::string name = path.string();
    std::string file_error, memory_error;
    Model from_file, from_memory;
    try {
      from_file = read_gltf(name);
    } catch (const Error& e) {
      file_error = e.what();
    }
    try {
      from_memory = read_gltf_memory(read_bytes(path), name);
    } catch (const Error& e) {
      memory_error = e.what();
    }
    if (memory_error.find("read from memory may only use data: URIs") != std::string::npos) {
      EXPECT_FALSE(file_error.empty()) << "every external URI in the catalogue is refused in file mode too";
      ++refused;
      continue;
    }
    EXPECT_EQ(file_error, memory_error);
    if (!file_error.empty()) {
      ++refused;
      continue;
    }
    ++accepted;
    expect_valid_model(from_file);
    const ModelStats a = compute_stats(from_file), b = compute_stats(from_memory);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.welded_vertices, b.welded_vertices);
    EXPECT_EQ(find_problems(from_file), find_problems(from_memory));
  }
  EXPECT_GE(accepted, 10u);
  EXPECT_GE(refused, 40u);
}

TEST(GltfRobustnessTest, memory_reader_never_opens_a_file) {
  // The model names an external buffer that exists beside it; from memory it must be refused.
  const fs::path path = kSource / "tests/data/bad/escape/uri_to_parent_folder.gltf";
  try {
    read_gltf_memory(read_bytes(path), "in-memory.gltf");
    FAIL() << "an external URI was accepted from memory";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("read from memory may only use data: URIs"), std::string::npos)
        << e.what();
  }
  // And the assets that embed everything read the same from memory as from their file.
  for (const auto& asset : test::asset_models()) {
    if (fs::path(asset).extension() != ".glb") continue;
    SCOPED_TRACE(asset);
    const Model a = read_gltf(asset), b = read_gltf_memory(read_bytes(asset), asset);
    EXPECT_EQ(compute_stats(a).triangles, compute_stats(b).triangles);
    EXPECT_EQ(compute_stats(a).welded_vertices, compute_stats(b).welded_vertices);
  }
}

TEST(GltfRobustnessTest, fuzz_regressions_and_seed_corpus_are_rejected_cleanly_or_valid) {
  const auto regressions = files_under(kSource / "tests/fuzz/regressions/gltf");
  const auto seeds = files_under(kSource / "tests/fuzz/corpus/gltf");
  ASSERT_GE(seeds.size(), 5u) << "the seed corpus is missing";
  for (const auto* list : {&regressions, &seeds})
    for (const auto& path : *list) {
      SCOPED_TRACE(path.string());
      expect_clean_outcome(read_bytes(path), path.filename().string());
    }
}

TEST(GltfRobustnessTest, every_prefix_of_a_glb_is_rejected_cleanly) {
  // Truncation at every length of a small skinned .glb (header, JSON chunk, BIN chunk).
  const auto glb = read_bytes(kSource / "tests/data/bad/control_simple_skin.glb");
  ASSERT_GT(glb.size(), 100u);
  const Model whole = read_gltf_memory(glb, "whole.glb");
  expect_valid_model(whole);
  for (std::size_t n = 0; n < glb.size(); ++n) {
    SCOPED_TRACE(n);
    const std::vector<unsigned char> prefix(glb.begin(), glb.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THROW(read_gltf_memory(prefix, "prefix.glb"), Error);
  }
}

TEST(GltfRobustnessTest, every_single_byte_flip_of_a_small_gltf_is_handled) {
  // Each byte of a small .gltf replaced by a byte that breaks structure ('"', '{', '9', 0xFF):
  // the reader must throw Error or return a model that satisfies the mesh invariants.
  const auto text = read_bytes(kSource / "tests/data/bad/control_textured.gltf");
  ASSERT_GT(text.size(), 1000u);
  for (std::size_t i = 0; i < text.size(); i += 3)
    for (const unsigned char b : {static_cast<unsigned char>('"'), static_cast<unsigned char>('{'),
                                  static_cast<unsigned char>('9'), static_cast<unsigned char>(0xFF)}) {
      auto mutated = text;
      mutated[i] = b;
      SCOPED_TRACE("byte " + std::to_string(i) + " -> " + std::to_string(b));
      expect_clean_outcome(mutated, "flip.gltf");
      if (HasFailure()) return;
    }
}

}  // namespace deepcut
