// SPDX-License-Identifier: MIT
// libFuzzer target for one static mesh format (DEEPCUT_FUZZ_FORMAT: obj, ply, stl or off; one
// executable each, so each keeps its own corpus). OFF text goes straight to parse_off; the other
// formats are written to a scratch file that read_static_model opens (VTK's readers read files
// only). Bad input must end in deepcut::Error; an accepted file must give a valid unrigged model.
// VTK itself is not instrumented for coverage, so for OBJ, PLY and STL the fuzzer steers by the
// project's checks around the readers.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/validate.h"
#include "deepcut/plugins/static_formats.h"

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz_read_%s: %s\n", DEEPCUT_FUZZ_FORMAT, what.c_str());
  std::abort();
}

const std::string& scratch_path() {
  static const std::string path = (std::filesystem::temp_directory_path() /
                                   ("deepcut-fuzz-" + std::to_string(::getpid()) + "." DEEPCUT_FUZZ_FORMAT))
                                      .string();
  return path;
}

void check_model(const deepcut::Model& model) {
  if (model.meshes.size() != 1 || model.skins.size() != 1 || model.skins[0].joints.size() != 1)
    finding("an accepted file did not give one mesh skinned to one joint");
  deepcut::validate_mesh(model.meshes[0].primitives.at(0).mesh, 1);
  (void)deepcut::find_problems(model);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  deepcut::Model model;
  try {
    if (std::string(DEEPCUT_FUZZ_FORMAT) == "off") {
      model = deepcut::make_static_model(deepcut::plugins::parse_off(bytes, "fuzz.off"), "fuzz", "fuzz.off");
    } else {
      {
        std::ofstream out(scratch_path(), std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      }
      model = deepcut::plugins::read_static_model(scratch_path());
    }
  } catch (const deepcut::Error& e) {
    if (!e.is_input_error()) finding(std::string("internal error: ") + e.what());
    if (std::string(e.what()).find('\n') != std::string::npos) finding("a message with a line break");
    return 0;
  } catch (const std::exception& e) {
    finding(std::string("exception that is not deepcut::Error: ") + e.what());
  }
  try {
    check_model(model);
  } catch (const std::exception& e) {
    finding(std::string("an accepted file gave an invalid model: ") + e.what());
  }
  return 0;
}
