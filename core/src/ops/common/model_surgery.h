// SPDX-License-Identifier: MIT
#pragma once
// Helpers shared by the Model-level operations (cut_model, drill_model). Private to core.

#include <vector>

#include "deepcut/core/model.h"

namespace deepcut::detail {

/// A copy of `mesh` holding only `faces` (unused vertices dropped, attributes following).
SurfaceMesh extract(const SurfaceMesh& mesh, const std::vector<FaceId>& faces);

/// Index of the model's "Cut surface" material (cut caps, drill walls), added on first use.
int cut_surface_material(Model& model);

}  // namespace deepcut::detail
