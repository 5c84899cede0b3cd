// SPDX-License-Identifier: MIT
#pragma once
// glTF export, compressed (private to core): rewrites the document the writer built, with its one
// binary buffer, into a Draco or meshopt compressed one. A separate pass over the finished JSON,
// so the writer states the model once and every object it writes (targets, animation data, images)
// is compressed or kept by the same rules.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "uninit_vector.h"

namespace deepcut::gltf_detail {

// `doc` describes `bin` as buffer 0 (`buffers[0]`, with a data URI when `glb` is false). After the
// call, `bin` holds the compressed data and what stays plain; views nothing refers to any more are
// gone, `extensionsUsed`/`extensionsRequired` name the codec, and for meshopt `buffers[1]` is the
// fallback buffer the extension specifies (no bytes in the file).
// Draco: every primitive's indices and vertex attributes (edgebreaker; sequential for a primitive
// with morph targets, whose plain target accessors must keep the vertex order, checked by decoding).
// Meshopt: every view one accessor reads whole (ATTRIBUTES) and every triangle index view
// (TRIANGLES); lossless.
// @throws Error{InvariantViolated} when a codec fails or cannot keep a primitive's morph targets
//         (write_gltf puts the file's name in front).
void compress_document(nlohmann::json& doc, detail::UninitVector<unsigned char>& bin, Compression compression, bool glb);

}  // namespace deepcut::gltf_detail
