// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cctype>
#include <iterator>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/plugins/formats.h"

namespace deepcut::plugins {

Model read_model(const std::string& path) {
  const FormatRegistry& formats = builtin_formats();
  if (const ModelFormat* format = find_format(formats, path)) return format->read(path);
  // Mesh formats users bring that no reader of this build takes: say so, instead of the glTF
  // parser's complaint about the first byte.
  static const char* const kKnownMeshFormats[] = {"obj", "ply", "stl", "off", "fbx", "dae", "3ds", "blend",
                                                   "usd", "usda", "usdc", "usdz", "abc", "x3d", "vtk", "vtp"};
  const std::size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    std::string ext = path.substr(dot + 1);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (std::find(std::begin(kKnownMeshFormats), std::end(kKnownMeshFormats), ext) != std::end(kKnownMeshFormats))
      throw Error(ErrorCode::InvalidInput, path + ": this build of DeepCut cannot read ." + ext + " files (it reads " +
                                               extensions(formats) + ")");
  }
  return read_gltf(path);
}

}  // namespace deepcut::plugins
