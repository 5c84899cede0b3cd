// SPDX-License-Identifier: MIT
#pragma once
/// @file weld.h
/// "Model optimisation" in the paper: merge vertices that a file duplicated at UV seams or hard
/// normals into one topological vertex. Corner attributes keep the seam, so nothing is lost.
/// The importers build the mesh as the file stores it (one vertex per file vertex, per-corner
/// data as corner attributes) and call `weld` with the key their format needs.

#include <cstddef>

#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// What two vertices must share to become one. Positions compare by value (+0 and -0 are equal);
/// every other vertex attribute compares bitwise. Morph position deltas
/// (`attr::morph_position_name`) are part of every key but `None`: two vertices that one morph
/// target moves apart are two vertices. Per-corner data (normals, their morph deltas) never is.
enum class WeldKey {
  /// Position and every other vertex attribute (a glTF primitive's joints, weights and morph
  /// position deltas): vertices at one position with different skin weights or deltas are kept
  /// apart (counted in `kept_apart`).
  PositionAndSkin,
  /// Position and morph position deltas (formats without skins): the merged vertex keeps the
  /// other vertex attributes of its first user.
  Position,
  /// No two vertices merge: unreferenced vertices are dropped and the rest renumbered.
  None,
};

struct WeldOptions {
  WeldKey key = WeldKey::PositionAndSkin;
  /// Also drops the faces that repeat a vertex once welded (two corners at one position); the
  /// vertices only those faces used are then dropped too.
  bool drop_repeating_faces = false;
};

struct WeldReport {
  std::size_t merged = 0;      ///< vertices merged into another (kept) vertex
  std::size_t kept_apart = 0;  ///< vertices sharing a position with another but not its skin weights or morph deltas
  std::size_t dropped = 0;     ///< vertices no kept face used, directly or through a merge
  std::size_t faces_dropped = 0;  ///< faces that repeated a vertex (with `drop_repeating_faces`)
};

/// Merges the vertices that `options.key` says are equal. Vertices are renumbered in order of
/// first use by the kept faces, and each keeps the attributes of its first user (that is, its
/// first user in the faces before any was dropped); unreferenced vertices are dropped; deleted
/// faces are removed.
/// The rebuilt vertex arrays and faces have the room to grow that operations get
/// (operation_room.h), so `reserve_for_operations` after an import copies none of them.
/// @note This rebuilds the mesh wholesale (an import step), so it records no edit log: build
///       `Adjacency` after it. O(#vertices + #faces) expected.
WeldReport weld(SurfaceMesh& mesh, const WeldOptions& options = {});

}  // namespace deepcut
