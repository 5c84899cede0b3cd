// SPDX-License-Identifier: MIT
#pragma once
// three.js as a second real client in the tests: scripts/pose_three.mjs poses a file with
// three's GLTFLoader and AnimationMixer, the project poses the same file (read without welding,
// so its faces are the file's triangles) through `PosedModel`, and the two are compared corner by
// corner at each time: the same mesh instances, every glTF vertex a triangle uses at the same
// world position, the same bounds, within a tolerance relative to the posed model's size.

#include <cstddef>
#include <string>
#include <vector>

namespace deepcut::test {

/// Empty when node and three.js can run scripts/pose_three.mjs; otherwise why not (tests then
/// skip, as the validator tests do without node).
std::string three_unavailable();

/// One file posed at some times of one animation (-1: the rest pose).
struct ThreePoseRequest {
  std::string file;
  int animation = -1;
  std::vector<float> times;
  /// Normalise three's rotation keys first, as the project's reader does: for input files, whose
  /// keys may be slightly off unit length (within the validator's tolerance); the project's
  /// exports are posed as stored.
  bool unit_rotations = false;
};

/// The first clip at 0.37 and 0.81 of its duration (two moments inside the clip), or the rest
/// pose when the file has no animation (as the project reads it).
ThreePoseRequest two_times_of_first_clip(const std::string& file, bool unit_rotations = false);

/// What the comparison of one request found.
struct ThreeComparison {
  std::string file;
  /// One line per disagreement (empty: three.js and the project agree); each names the time.
  std::vector<std::string> problems;
  std::size_t instances = 0;  ///< mesh instances compared (per pose)
  std::size_t corners = 0;    ///< triangle corners compared, all poses together
  float worst = 0.0f;         ///< largest distance found, relative to the posed model size
};

/// Poses every request with three.js (one node process for all) and with the project, and
/// compares them: instance sets by (node, primitive), face counts, every triangle corner's posed
/// world position and the posed bounds, each within `tolerance` x the diagonal of the project's
/// posed bounds at that time. A file either side cannot read is a problem, not an exception.
std::vector<ThreeComparison> compare_with_three(const std::vector<ThreePoseRequest>& requests,
                                                float tolerance = 1e-5f);

}  // namespace deepcut::test
