// SPDX-License-Identifier: MIT
#include "deepcut/core/io/gltf.h"
#include "deepcut/plugins/formats.h"

namespace deepcut::plugins {

Model read_model(const std::string& path) {
  if (const ModelFormat* format = builtin_formats().find(path)) return format->read(path);
  return read_gltf(path);
}

}  // namespace deepcut::plugins
