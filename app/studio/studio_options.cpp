// SPDX-License-Identifier: MIT
#include "studio_options.h"

#include "anti_aliasing.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace deepcut::studio {

const char* studio_usage() {
  return "usage: deepcut-studio [MODEL] [options]\n"
         "\n"
         "Opens MODEL (.glb, .gltf, or a static .obj, .ply, .stl, .off mesh; default: the bundled\n"
         "assets/cactus.glb) in the studio.\n"
         "\n"
         "options:\n"
         "  --screenshot OUT.png     render one frame of the window to OUT.png and exit\n"
         "  --inspect ID             start with an inspector: weights, adjacency, clusters, ... or none\n"
         "  --joint NAME             weights inspector: show the weights of joint NAME\n"
         "  --vertex N               adjacency inspector: pick vertex N of the first mesh\n"
         "  --animation N|NAME       choose the animation (index or name)\n"
         "  --time T                 pose time in seconds\n"
         "  --apply HISTORY.json     run the operations of a history file (as deepcut apply) after opening\n"
         "  --look-at X,Y,Z,R        point the camera at the sphere of radius R around X,Y,Z (world)\n"
         "  --view shaded|wireframe|edges\n"
         "  --normals                show normals\n"
         "  --anti-aliasing auto|on|off\n"
         "                           multisampling of the view (default: the View menu's choice;\n"
         "                           auto turns it off on a software renderer; screenshots: on)\n"
         "  --frame                  zoom to the inspector's selection (picked vertex, joint)\n"
         "  --no-skeleton            hide the skeleton\n"
         "  --size WxH               window size (default 1440x900)\n"
         "\n"
         "exit codes: 0 ok, 2 bad input or usage (one line on stderr), 1 internal error\n";
}

namespace {

float parse_time(const std::string& t) {
  std::size_t used = 0;
  float seconds = 0.0f;
  try {
    seconds = std::stof(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != t.size() || t.empty() || !std::isfinite(seconds) || seconds < 0.0f)
    throw UsageError("--time must be a number of seconds >= 0, not '" + t + "'");
  return seconds;
}

std::array<float, 4> parse_look_at(const std::string& text) {
  std::array<float, 4> v{};
  char extra = 0;
  if (std::sscanf(text.c_str(), "%f,%f,%f,%f%c", &v[0], &v[1], &v[2], &v[3], &extra) != 4 ||
      !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !std::isfinite(v[3]) ||
      !(v[3] > 0.0f))
    throw UsageError("--look-at must be X,Y,Z,R (finite, R > 0), not '" + text + "'");
  return v;
}

void parse_size(const std::string& s, StudioOptions& o) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 320 || h < 240 ||
      w > 8192 || h > 8192)
    throw UsageError("--size must be WIDTHxHEIGHT between 320x240 and 8192x8192, not '" + s + "'");
  o.width = w;
  o.height = h;
}

/// Sets the flag `arg` (an option without a value) in `o`. @returns false if `arg` is no flag.
bool set_flag(const std::string& arg, StudioOptions& o) {
  if (arg == "-h" || arg == "--help")
    o.help = true;
  else if (arg == "--normals")
    o.normals = true;
  else if (arg == "--frame")
    o.frame = true;
  else if (arg == "--no-skeleton")
    o.skeleton = false;
  else
    return false;
  return true;
}

/// Sets the option `arg` to its value (`take()`, checked) in `o`. @returns false if `arg` is no
/// option with a value.
template <class Take>
bool set_valued(const std::string& arg, Take&& take, StudioOptions& o) {
  if (arg == "--screenshot") {
    o.screenshot = take();
    if (o.screenshot.empty()) throw UsageError("--screenshot needs a file name");
  } else if (arg == "--inspect") {
    o.inspect = take();
  } else if (arg == "--joint") {
    o.joint = take();
  } else if (arg == "--vertex") {
    o.vertex = take();
  } else if (arg == "--animation") {
    o.animation = take();
  } else if (arg == "--time") {
    o.time = parse_time(take());
  } else if (arg == "--apply") {
    o.apply = take();
    if (o.apply.empty()) throw UsageError("--apply needs a history file (.json)");
  } else if (arg == "--look-at") {
    o.look_at = parse_look_at(take());
  } else if (arg == "--view") {
    o.view = take();
    if (o.view != "shaded" && o.view != "wireframe" && o.view != "edges")
      throw UsageError("--view must be shaded, wireframe or edges, not '" + o.view + "'");
  } else if (arg == "--anti-aliasing") {
    o.anti_aliasing = take();
    if (!parse_anti_aliasing(o.anti_aliasing))
      throw UsageError("--anti-aliasing must be auto, on or off, not '" + o.anti_aliasing + "'");
  } else if (arg == "--size") {
    parse_size(take(), o);
  } else {
    return false;
  }
  return true;
}

}  // namespace

StudioOptions parse_studio_options(const std::vector<std::string>& args) {
  StudioOptions o;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string arg = args[i];
    std::string value;
    bool has_inline = false;
    if (arg.rfind("--", 0) == 0) {
      const auto eq = arg.find('=');
      if (eq != std::string::npos) {
        value = arg.substr(eq + 1);
        arg = arg.substr(0, eq);
        has_inline = true;
      }
    }
    auto take = [&]() -> std::string {
      if (has_inline) return value;
      if (i + 1 >= args.size()) throw UsageError(arg + " needs a value");
      return args[++i];
    };
    if (set_flag(arg, o) || set_valued(arg, take, o)) continue;
    if (arg.size() > 1 && arg[0] == '-') throw UsageError("unknown option '" + arg + "'");
    if (!o.model.empty()) throw UsageError("more than one MODEL ('" + o.model + "' and '" + arg + "')");
    o.model = arg;
  }
  return o;
}

std::string default_model_path(const std::string& exe_dir, std::vector<std::string>* searched) {
  namespace fs = std::filesystem;
  const fs::path dir(exe_dir);
  std::vector<fs::path> candidates = {dir / ".." / ".." / "assets" / "cactus.glb",
                                      dir / ".." / "share" / "deepcut" / "assets" / "cactus.glb"};
#ifdef DEEPCUT_SOURCE_ASSETS_DIR
  // A build tree anywhere (not only build/ inside the sources) still finds the source assets.
  candidates.push_back(fs::path(DEEPCUT_SOURCE_ASSETS_DIR) / "cactus.glb");
#endif
  for (const fs::path& p : candidates) {
    if (searched) searched->push_back(p.lexically_normal().string());
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p.lexically_normal().string();
  }
  return {};
}

}  // namespace deepcut::studio
