// SPDX-License-Identifier: MIT
#pragma once
// Equality of one node or one mesh of a model, as same_structure (model_change.h) compares them:
// floats bit for bit, a primitive's attribute names and types but not its element data. For undo
// records that share the parts of a model equal to another's (model_undo_parts.h, KeptShell).

#include "deepcut/core/model.h"

namespace deepcut::detail {

bool same_part(const Node& a, const Node& b);
bool same_part(const Mesh& a, const Mesh& b);

}  // namespace deepcut::detail
