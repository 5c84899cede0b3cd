// SPDX-License-Identifier: MIT
// libFuzzer target: the glTF reader on arbitrary bytes (as .glb or .gltf, from memory).
// Bad input must end in deepcut::Error; anything else (a crash, a sanitizer report, another
// exception, a hang or an allocation past -rss_limit_mb) is a finding. Input the reader accepts
// must also hold the mesh invariants and survive an export + re-import with the same counts.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/validate.h"

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz_read_gltf: %s\n", what.c_str());
  std::abort();
}

// Every accepted model must satisfy what the operations rely on.
void check_model(const deepcut::Model& model) {
  std::vector<std::size_t> joints(model.meshes.size(), 0);
  for (const auto& n : model.nodes)
    if (n.mesh >= 0 && n.skin >= 0)
      joints[static_cast<std::size_t>(n.mesh)] = model.skins[n.skin].joints.size();
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    for (const auto& prim : model.meshes[m].primitives) deepcut::validate_mesh(prim.mesh, joints[m]);
  (void)deepcut::find_problems(model);
}

const std::string& scratch_path() {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("deepcut-fuzz-" + std::to_string(::getpid()) + ".glb"))
          .string();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<unsigned char> bytes(data, data + size);
  deepcut::Model model;
  try {
    model = deepcut::read_gltf_memory(bytes, "fuzz.gltf");
  } catch (const deepcut::Error& e) {
    if (e.code() != deepcut::ErrorCode::InvalidInput)
      finding(std::string("unexpected error code: ") + e.what());
    return 0;  // rejected cleanly
  } catch (const std::exception& e) {
    finding(std::string("exception that is not deepcut::Error: ") + e.what());
  }
  try {
    check_model(model);
    const deepcut::ModelStats before = deepcut::compute_stats(model);
    deepcut::write_gltf(model, scratch_path());
    const deepcut::Model back = deepcut::read_gltf(scratch_path());
    const deepcut::ModelStats after = deepcut::compute_stats(back);
    std::remove(scratch_path().c_str());
    if (after.triangles != before.triangles) finding("export + re-import changed the triangle count");
    check_model(back);
  } catch (const std::exception& e) {
    std::remove(scratch_path().c_str());
    finding(std::string("an accepted model failed its checks or its round trip: ") + e.what());
  }
  return 0;
}
