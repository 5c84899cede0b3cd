// SPDX-License-Identifier: MIT
#pragma once
// Command line of deepcut-studio, and where the bundled default model is.

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace deepcut::studio {

/// A malformed command line (exit code 2).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StudioOptions {
  std::string model;               ///< MODEL; empty: the bundled default model
  std::string screenshot;          ///< --screenshot OUT.png: render one frame of the window and exit
  std::string inspect;             ///< --inspect ID
  std::string joint;               ///< --joint NAME (weights inspector)
  std::string vertex;              ///< --vertex N (adjacency inspector: the picked vertex)
  std::string animation;           ///< --animation N|NAME
  std::string apply;               ///< --apply HISTORY.json: run its operations (undoable) after opening
  std::optional<std::array<float, 4>> look_at;  ///< --look-at X,Y,Z,R: zoom to that sphere (world)
  std::optional<float> time;       ///< --time T, seconds
  std::string view = "shaded";     ///< --view shaded|wireframe|edges
  bool normals = false;            ///< --normals
  std::string anti_aliasing;       ///< --anti-aliasing auto|on|off; empty: the saved choice (screenshots: on)
  bool frame = false;              ///< --frame: zoom to the inspector's selection
  bool skeleton = true;            ///< --no-skeleton turns it off
  int width = 1440, height = 900;  ///< --size WxH (screenshots)
  bool help = false;
};

/// Parses the arguments after the program name (Qt's own, such as -platform, already removed).
/// @throws UsageError naming the bad argument.
StudioOptions parse_studio_options(const std::vector<std::string>& args);

/// The usage text.
const char* studio_usage();

/// The bundled default model next to the executable in `exe_dir`: `../../assets/cactus.glb`
/// (a build tree), then `../share/deepcut/assets/cactus.glb` (an install), then the source
/// tree's `assets/cactus.glb` this program was built from (an out-of-tree build).
/// @returns the first that exists, or "" with `searched` listing the candidates.
std::string default_model_path(const std::string& exe_dir, std::vector<std::string>* searched = nullptr);

}  // namespace deepcut::studio
