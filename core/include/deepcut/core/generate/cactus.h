// SPDX-License-Identifier: MIT
#pragma once
/// @file generate/cactus.h
/// The project's own rigged test model: a ribbed cactus (trunk and two arms), each limb a closed
/// surface with cylindrical UVs (one seam), a joint chain per limb, smooth skin weights and a
/// looping sway animation. The default size matches the paper's cactus (~25 300 triangles).

#include "deepcut/core/model.h"

namespace deepcut {

struct CactusOptions {
  /// Approximate triangle count; resolution scales with its square root (default: the paper's).
  std::size_t target_triangles = 25300;
  /// Overall height in model units (the trunk's length from ground to the top of its dome).
  float height = 10.0f;
  /// Length of the looping sway animation, in seconds.
  float animation_seconds = 4.0f;
};

/// Builds the cactus. Deterministic: the same options give the same model.
/// @throws Error{InvalidArgument} if target_triangles is below 1000 or above 200 million, or
///         height or animation_seconds is not a positive finite number.
Model make_cactus(const CactusOptions& options = {});

}  // namespace deepcut
