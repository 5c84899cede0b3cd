// SPDX-License-Identifier: MIT
#pragma once
/// @file generate/cactus_morph.h
/// The cactus's blend shapes (private to the generator): target 0 "arms_lift" raises both arms,
/// target 1 "bloom" swells a bulb on top of the trunk. Position deltas per vertex, normal deltas
/// per corner computed by the generator's own normal rule on the fully morphed surface, and the
/// looping weight animation that plays them in the cactus's clip, so the default model
/// exercises skinning and morphing together.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut::cactus_morph {

/// Names of the targets, in target order.
inline const std::array<std::string, 2> kTargetNames = {"arms_lift", "bloom"};

/// Where the shapes act, in model units.
struct Shape {
  double height = 10.0;  ///< the cactus's height (the trunk's top pole)
  /// Top of the trunk's straight body (where its top dome begins) and the dome's axial extent.
  double dome_base_y = 9.0;
  double dome_height = 0.8;
  /// Per arm: spine coordinate where it leaves the trunk (no lift) and where its bend ends (full
  /// lift from there to the tip).
  struct Arm {
    double start_s = 0.0, full_s = 1.0;
  };
  std::array<Arm, 2> arms;
};

/// The sweep's record of each vertex: its limb (0 trunk, 1 and 2 the arms) and spine coordinate.
struct VertexOrigin {
  std::vector<std::uint8_t> limb;
  std::vector<float> spine_s;
};

/// The generator's normal rule: corner c's normal is the normalised area-weighted sum of the face
/// normals of every corner sharing its slot `slots[c]` (the analytic pole normals excepted).
struct NormalSlots {
  const std::vector<std::uint32_t>& slots;  ///< per corner
  std::size_t count = 0;                    ///< number of slots
};

/// Adds both targets to `mesh` (positions per vertex, normal deltas per corner, so the morphed
/// normals follow the same rule as the rest normals).
void add_targets(SurfaceMesh& mesh, const VertexOrigin& origin, const Shape& shape, const NormalSlots& normals);

/// Fills the mesh's `weights` (zeros), `target_names` and `extras_json` ({"targetNames": ...}).
void describe_targets(Mesh& mesh);

/// The weight channel's sampler: both weights 0 at the clip's start and end (the loop is
/// seamless), the arms rising once and the bloom swelling twice per loop; keys at
/// `keys_per_second`, linear.
AnimationSampler weight_sampler(float seconds, float keys_per_second);

}  // namespace deepcut::cactus_morph
