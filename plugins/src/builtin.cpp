// SPDX-License-Identifier: MIT
// The model formats built into every program (command line and studio), in the order a file's
// extension is looked up: one line per format plugin.
#include "deepcut/plugins/formats.h"
#if DEEPCUT_HAVE_STATIC_FORMATS
#include "deepcut/plugins/static_formats.h"
#endif

namespace deepcut::plugins {

const FormatRegistry& builtin_formats() {
  static const FormatRegistry registry = [] {
    FormatRegistry r;
    register_gltf(r);
#if DEEPCUT_HAVE_STATIC_FORMATS
    register_static_formats(r);  // OBJ, PLY, STL (VTK readers) and OFF: the build with VTK
#endif
    return r;
  }();
  return registry;
}

}  // namespace deepcut::plugins
