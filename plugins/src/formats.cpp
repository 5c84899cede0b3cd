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

void check_entry(ModelFormat& format, const std::vector<ModelFormat>& taken) {
  if (format.name.empty() || format.extensions.empty() || !format.read)
    throw Error(ErrorCode::InvalidArgument, "format registry: a format needs a name, extensions and a reader");
  for (std::string& ext : format.extensions) {
    ext = lower(ext);
    if (ext.empty() || ext[0] == '.')
      throw Error(ErrorCode::InvalidArgument, "format registry: '" + format.name + "' has an empty or dotted extension");
    for (const ModelFormat& other : taken)
      if (std::find(other.extensions.begin(), other.extensions.end(), ext) != other.extensions.end())
        throw Error(ErrorCode::InvalidArgument, "format registry: ." + ext + " is read by '" + other.name + "' already");
  }
}

const ModelFormat* find_format(const FormatRegistry& registry, const std::string& path) {
  const std::string ext = extension_of(path);
  for (const ModelFormat& f : registry.list())
    if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) return &f;
  return nullptr;
}

std::string extensions(const FormatRegistry& registry) {
  std::string out;
  for (const ModelFormat& f : registry.list())
    for (const std::string& ext : f.extensions) out += (out.empty() ? "." : " .") + ext;
  return out;
}

void check_registry_id(const std::string& id, bool taken) {
  if (id.empty()) throw Error(ErrorCode::InvalidArgument, "plugin registry: an entry has no id");
  if (taken) throw Error(ErrorCode::InvalidArgument, "plugin registry: '" + id + "' is registered twice");
}

void register_gltf(FormatRegistry& registry) {
  registry.add({"glTF", {"glb", "gltf"}, [](const std::string& path) { return read_gltf(path); }});
}

}  // namespace deepcut::plugins
