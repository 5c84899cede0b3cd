// SPDX-License-Identifier: MIT
#include "deepcut/plugins/formats.h"

#include <algorithm>
#include <cctype>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"

namespace deepcut::plugins {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot + 1));
}

}  // namespace

void FormatRegistry::add(ModelFormat format) {
  if (format.name.empty() || format.extensions.empty() || !format.read)
    throw Error(ErrorCode::InvalidArgument, "format registry: a format needs a name, extensions and a reader");
  for (std::string& ext : format.extensions) {
    ext = lower(ext);
    if (ext.empty() || ext[0] == '.')
      throw Error(ErrorCode::InvalidArgument, "format registry: '" + format.name + "' has an empty or dotted extension");
    for (const ModelFormat& other : formats_)
      if (std::find(other.extensions.begin(), other.extensions.end(), ext) != other.extensions.end())
        throw Error(ErrorCode::InvalidArgument, "format registry: ." + ext + " is read by '" + other.name + "' already");
  }
  formats_.push_back(std::move(format));
}

const ModelFormat* FormatRegistry::find(const std::string& path) const {
  const std::string ext = extension_of(path);
  for (const ModelFormat& f : formats_)
    if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) return &f;
  return nullptr;
}

std::string FormatRegistry::extensions() const {
  std::string out;
  for (const ModelFormat& f : formats_)
    for (const std::string& ext : f.extensions) out += (out.empty() ? "." : " .") + ext;
  return out;
}

void register_gltf(FormatRegistry& registry) {
  registry.add({"glTF", {"glb", "gltf"}, [](const std::string& path) { return read_gltf(path); }});
}

}  // namespace deepcut::plugins
