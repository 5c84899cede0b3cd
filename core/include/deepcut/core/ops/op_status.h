// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/op_status.h

namespace deepcut {

/// Outcome of an operation on valid input. Invalid input throws `Error` instead.
enum class OpStatus {
  Ok,             ///< the mesh changed
  NoIntersection  ///< the tool missed the model: mesh untouched, edit log empty
};

inline const char* to_string(OpStatus s) { return s == OpStatus::Ok ? "ok" : "no_intersection"; }

}  // namespace deepcut
