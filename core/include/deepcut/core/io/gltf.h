// SPDX-License-Identifier: MIT
#pragma once
/// @file io/gltf.h
/// glTF 2.0 import and export (.gltf with embedded or external buffers, and .glb).

#include <string>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut {

struct ImportOptions {
  /// Weld glTF vertices that share position and skin into one topological vertex (default on).
  bool weld = true;
};

/// Reads a .gltf or .glb file. Triangle primitives (also strips and fans, converted) become welded
/// `SurfaceMesh`es; skins without inverseBindMatrices get identity matrices; weights are
/// normalised. Morph targets become `attr::morph_*` attributes (position deltas per vertex, normal
/// and tangent deltas per corner), `Mesh::weights` has one weight per target, and node weights and
/// weight channels that do not fit their mesh's targets are fitted or dropped (repairs are listed
/// in `Model::import_problems`).
/// @throws Error{Io} when the file cannot be read, Error{InvalidInput} when it is malformed
///         (the message starts with the file name and says what is wrong).
Model read_gltf(const std::string& path, const ImportOptions& options = {});

/// Reads a .glb or .gltf held in memory (fuzzing, data from a network or an archive).
/// @param bytes  the whole file.
/// @param name   names the input in messages; a name ending in .glb demands the .glb magic.
/// @note No file is ever opened: external URIs are refused, so only a .glb's BIN chunk and
///       `data:` URIs supply buffers and images. Otherwise the same as `read_gltf`.
/// @throws Error{InvalidInput} when malformed (the message starts with `name`).
Model read_gltf_memory(const std::vector<unsigned char>& bytes, const std::string& name,
                       const ImportOptions& options = {});

/// How `write_gltf` stores mesh data. Compressed files require the extension of their codec
/// (`extensionsRequired`), so only readers that decode it can open them.
enum class Compression {
  None,     ///< plain accessors (the default)
  Draco,    ///< KHR_draco_mesh_compression: triangles and vertex attributes, quantised
            ///< (positions 14 bits, normals 10, texture coordinates 12; skin weights and
            ///< colours lossless); morph targets stay plain accessors in the decoded vertex order
  Meshopt,  ///< EXT_meshopt_compression: every vertex, index and animation buffer view, lossless
};

/// "none", "draco", "meshopt" -> the Compression; false for anything else.
bool parse_compression(const std::string& name, Compression* out);

struct ExportOptions {
  /// Pretty-print the JSON of .gltf files (default on; .glb JSON is always compact).
  bool pretty = true;
  std::string generator = "DeepCut Studio";
  Compression compression = Compression::None;
};

/// Writes `model` as .glb or .gltf (by extension; a .gltf embeds its buffer as a data URI).
/// Corners are un-welded into glTF vertices; weights normalised, zero-weight joints set to 0,
/// POSITION min/max written. A mesh writes as many morph targets as `Mesh::weights` says and all
/// its primitives carry; a weight channel or node weights whose node no longer draws such a mesh
/// are left out, so the file stays valid glTF. Written to a temporary file in the same folder,
/// then renamed, so a failure never leaves a partial file.
/// @throws Error{InvalidArgument} for an unknown extension, Error{Io} when writing fails.
void write_gltf(const Model& model, const std::string& path, const ExportOptions& options = {});

}  // namespace deepcut
