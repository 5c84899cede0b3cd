// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/plugins/formats.h"

namespace deepcut::plugins {
namespace {

/// True when the file at `path` opens and its first bytes are neither the .glb magic nor the
/// start of a JSON object (after white space or a UTF-8 byte order mark): no glTF at all.
bool surely_not_gltf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[64] = {};
  if (!in.read(head, sizeof head) && in.gcount() == 0) return false;  // missing or empty: the reader says so
  const std::string text(head, static_cast<std::size_t>(in.gcount()));
  if (text.compare(0, 4, "glTF") == 0) return false;
  std::size_t i = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  return i < text.size() && text[i] != '{';
}

}  // namespace

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
  if (surely_not_gltf(path)) {
    const std::string reads = extensions(formats);
    throw Error(ErrorCode::InvalidInput, path + ": not a model file (this build reads " + reads +
                                             "; glTF also by its content, and this file holds no glTF)");
  }
  return read_gltf(path);
}

}  // namespace deepcut::plugins
