// SPDX-License-Identifier: MIT
#pragma once
/// @file formats.h
/// Model file formats: which reader opens which file. glTF (.glb, .gltf) is built in; format
/// plugin folders (`plugins/NAME/`) define `void deepcut::plugins::register_NAME(FormatRegistry&)`
/// and add more, in the order plugins/src/builtin.cpp lists them. The command line and the
/// studio both open models through `read_model`, so a new format reaches both at once. No Qt.

#include <functional>
#include <string>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/plugins/registry.h"

namespace deepcut::plugins {

struct ModelFormat {
  std::string name;                     ///< "Wavefront OBJ": the file dialog's filter name
  std::vector<std::string> extensions;  ///< lower case, without the dot: {"obj"}
  /// Reads the file at `path`. @throws Error{InvalidInput} or Error{Io}, the message starting
  /// with `path` and saying what is wrong.
  std::function<Model(const std::string& path)> read;
};

inline const std::string& registry_id(const ModelFormat& format) { return format.name; }
/// Lowers the extensions. @throws Error{InvalidArgument} if the name or the extensions are empty,
/// an extension is dotted or read by a `taken` format already, or `read` is empty.
void check_entry(ModelFormat& format, const std::vector<ModelFormat>& taken);

using FormatRegistry = Registry<ModelFormat>;

/// The format reading files like `path` (by extension, case-insensitive), or nullptr.
const ModelFormat* find_format(const FormatRegistry& registry, const std::string& path);
/// Every extension, with dots, space separated (".glb .gltf .obj").
std::string extensions(const FormatRegistry& registry);

/// Registers the built-in glTF reader (.glb, .gltf).
void register_gltf(FormatRegistry& registry);

/// glTF first, then the format plugins in list order.
const FormatRegistry& builtin_formats();

/// Reads `path` with the built-in format its extension names; a file with another extension is
/// read as glTF, which recognises .glb and .gltf by their content (and refuses anything else).
/// @throws Error as the reader does; Error{InvalidInput} naming the file and the extensions this
///         build reads when the extension is a well-known mesh format no built-in reader takes
///         (.obj in a build without the static formats plugin), or when a file of another
///         extension starts with neither the .glb magic nor a JSON object ("not a model
///         file"), rather than a glTF parse error.
Model read_model(const std::string& path);

}  // namespace deepcut::plugins
