// SPDX-License-Identifier: MIT
#pragma once
/// @file material_look.h
/// How a glTF material looks in the viewer: base colour factor and texture, read from the
/// material JSON the model carries through untouched. No VTK here.

#include <glm/glm.hpp>
#include <string>

#include "deepcut/core/model.h"

namespace deepcut {

struct MaterialLook {
  std::string name;
  /// pbrMetallicRoughness.baseColorFactor (default opaque light grey when the primitive has no
  /// material, glTF's white when the material gives none).
  glm::vec4 base_color{0.78f, 0.78f, 0.78f, 1.0f};
  /// Index into `Model::images` of the base colour texture's image, or -1.
  int base_color_image = -1;
  /// TEXCOORD set of the base colour texture (default 0).
  int texcoord = 0;
  float metallic = 1.0f, roughness = 1.0f;  ///< glTF defaults
  bool double_sided = false;
  bool blend = false;  ///< alphaMode BLEND
};

/// The look of material `material` of `model` (-1: no material).
/// @returns defaults for a missing or out-of-range material; a malformed material JSON gives
///          the defaults too (the importer accepted the file, the viewer must still draw it).
MaterialLook material_look(const Model& model, int material);

}  // namespace deepcut
