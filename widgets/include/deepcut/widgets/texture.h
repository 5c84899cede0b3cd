// SPDX-License-Identifier: MIT
#pragma once
/// @file texture.h
/// glTF images (encoded PNG or JPEG bytes) as VTK textures. Include only in .cpp files.

#include <vtkSmartPointer.h>
#include <vtkTexture.h>

#include "deepcut/core/model.h"

namespace deepcut {

/// Decodes `image` and wraps it in a texture (linear filtering, mipmaps, repeat), laid out so
/// that glTF texture coordinates (v pointing down the image) map as in glTF.
/// @throws Error{InvalidInput} when the bytes are neither PNG nor JPEG, do not decode, or claim
///         more than 64 Mpixels.
vtkSmartPointer<vtkTexture> make_texture(const Image& image);

}  // namespace deepcut
