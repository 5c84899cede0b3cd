// SPDX-License-Identifier: MIT
#include "commands.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/plugins/formats.h"
#include "deepcut/core/validate.h"
#include "args.h"

namespace deepcut::cli {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::string single_model(const Args& args, const char* command) {
  if (args.positionals().size() != 1)
    throw UsageError(std::string(command) + " needs exactly one MODEL (.glb, .gltf, .obj, .ply, .stl or .off), got " +
                     std::to_string(args.positionals().size()));
  return args.positionals()[0];
}

std::string output_path(const Args& args, const char* command) {
  if (!args.has("-o")) throw UsageError(std::string(command) + " needs -o OUT (.glb or .gltf)");
  return args.value("-o");
}

const char* interpolation_name(Interpolation i) {
  return i == Interpolation::Step ? "step" : i == Interpolation::CubicSpline ? "cubic spline" : "linear";
}

// Each mesh with morph targets: its target count, names and default weights.
json morph_targets_json(const Model& model) {
  json out = json::array();
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const Mesh& mesh = model.meshes[m];
    if (mesh.target_count() == 0) continue;
    out.push_back({{"mesh", m}, {"name", mesh.name}, {"targets", mesh.target_count()}, {"names", mesh.target_names},
                   {"weights", mesh.weights}});
  }
  return out;
}

// Each animation channel on morph weights: the node it drives, its targets, keys, interpolation.
json weight_channels_json(const Model& model) {
  json out = json::array();
  for (std::size_t a = 0; a < model.animations.size(); ++a)
    for (const auto& ch : model.animations[a].channels) {
      if (ch.path != AnimationPath::Weights) continue;
      const AnimationSampler& s = model.animations[a].samplers[std::size_t(ch.sampler)];
      out.push_back({{"animation", a}, {"animation_name", model.animations[a].name}, {"node", ch.node},
                     {"node_name", model.nodes[std::size_t(ch.node)].name}, {"targets", s.components},
                     {"keys", s.input.size()}, {"interpolation", interpolation_name(s.interpolation)}});
    }
  return out;
}

// The text form of the two lists above (nothing for a model without morph targets).
void print_morphs(const Model& model) {
  for (const auto& m : morph_targets_json(model)) {
    std::cout << "\n  morph targets: mesh " << m["mesh"] << " '" << m["name"].get<std::string>() << "' " << m["targets"];
    if (!m["names"].empty()) {
      std::cout << " (";
      for (std::size_t i = 0; i < m["names"].size(); ++i) std::cout << (i ? ", " : "") << m["names"][i].get<std::string>();
      std::cout << ")";
    }
    std::cout << ", weights " << m["weights"].dump();
  }
  for (const auto& c : weight_channels_json(model))
    std::cout << "\n  weight channel: '" << c["animation_name"].get<std::string>() << "' -> node " << c["node"] << " '"
              << c["node_name"].get<std::string>() << "' (" << c["targets"] << " targets, " << c["keys"] << " keys, "
              << c["interpolation"].get<std::string>() << ")";
}

}  // namespace

int run_info(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json"}, {});
  const std::string path = single_model(args, "info");
  const auto t0 = Clock::now();
  const Model model = plugins::read_model(path);
  const double load_ms = ms_since(t0);
  const ModelStats s = compute_stats(model);
  auto problems = find_problems(model);
  // A file with nothing to draw is a problem for every command that edits meshes.
  const bool reported = std::any_of(problems.begin(), problems.end(),
                                    [](const std::string& p) { return p.find("no triangles") != std::string::npos; });
  if (s.meshes == 0) problems.push_back("the scene has no mesh");
  else if (s.triangles == 0 && !reported) problems.push_back("the mesh has no triangles");
  json anims = json::array();
  for (const auto& a : model.animations) anims.push_back({{"name", a.name}, {"duration", a.duration()}});
  std::size_t merged = 0;
  for (const auto& m : model.meshes)
    for (const auto& p : m.primitives) merged += p.welded_merged;
  const glm::vec3 lo = s.bounds.empty() ? glm::vec3(0.0f) : s.bounds.min, hi = s.bounds.empty() ? glm::vec3(0.0f) : s.bounds.max;
  if (args.flag("--json")) {
    json out = {{"file", path},
                {"nodes", s.nodes},
                {"meshes", s.meshes},
                {"primitives", s.primitives},
                {"vertices", s.gltf_vertices},
                {"welded_vertices", s.welded_vertices},
                {"weld_merged", merged},
                {"triangles", s.triangles},
                {"skins", s.skins},
                {"joints", s.joints},
                {"animations", s.animations},
                {"animation_clips", anims},
                {"morph_targets", morph_targets_json(model)},
                {"weight_channels", weight_channels_json(model)},
                {"materials", s.materials},
                {"textures", s.textures},
                {"images", s.images},
                {"boundary_edges", s.boundary_edges},
                {"nonmanifold_edges", s.nonmanifold_edges},
                {"seam_edges", s.seam_edges},
                {"components", s.components},
                {"bbox", {{"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}}},
                {"problems", problems},
                {"load_ms", load_ms}};
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::cout << path << "\n"
            << "  nodes " << s.nodes << ", meshes " << s.meshes << ", primitives " << s.primitives << "\n"
            << "  vertices " << s.gltf_vertices << " (glTF), " << s.welded_vertices << " welded (" << merged
            << " merged), triangles " << s.triangles << "\n"
            << "  skins " << s.skins << ", joints " << s.joints << ", materials " << s.materials << ", textures "
            << s.textures << ", images " << s.images << "\n"
            << "  animations " << s.animations;
  for (const auto& a : model.animations)
    std::cout << "\n    '" << a.name << "' " << std::setprecision(4) << a.duration() << " s";
  print_morphs(model);
  std::cout << "\n  edges: boundary " << s.boundary_edges << ", non-manifold " << s.nonmanifold_edges << ", seam "
            << s.seam_edges << "; components " << s.components << "\n"
            << "  bbox (rest pose) [" << lo.x << ", " << lo.y << ", " << lo.z << "] - [" << hi.x << ", " << hi.y << ", "
            << hi.z << "]\n"
            << "  problems: " << (problems.empty() ? "none" : std::to_string(problems.size())) << "\n";
  for (const auto& p : problems) std::cout << "    - " << p << "\n";
  return 0;
}

int run_convert(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json"}, {"-o"});
  const std::string in = single_model(args, "convert");
  const std::string out = output_path(args, "convert");
  const auto t0 = Clock::now();
  const Model model = plugins::read_model(in);
  const double read_ms = ms_since(t0);
  const auto t1 = Clock::now();
  write_gltf(model, out);
  const double write_ms = ms_since(t1);
  if (args.flag("--json")) {
    const ModelStats s = compute_stats(model);
    std::cout << json{{"input", in}, {"output", out}, {"triangles", s.triangles}, {"welded_vertices", s.welded_vertices},
                      {"read_ms", read_ms}, {"write_ms", write_ms}}
                     .dump(2)
              << "\n";
  } else {
    std::cerr << "deepcut: wrote " << out << "\n";
  }
  return 0;
}

int run_make_cactus(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json"}, {"-o", "--triangles", "--height"});
  if (!args.positionals().empty()) throw UsageError("make-cactus takes no MODEL, only -o OUT");
  const std::string out = output_path(args, "make-cactus");
  CactusOptions options;
  const long long tris = args.integer("--triangles", static_cast<long long>(options.target_triangles));
  if (tris < 1000 || tris > 200000000)
    throw UsageError("--triangles must be a whole number between 1000 and 200000000");
  options.target_triangles = static_cast<std::size_t>(tris);
  options.height = static_cast<float>(args.number("--height", options.height));
  const auto t0 = Clock::now();
  const Model model = make_cactus(options);
  const double make_ms = ms_since(t0);
  write_gltf(model, out);
  const ModelStats s = compute_stats(model);
  if (args.flag("--json")) {
    std::cout << json{{"output", out}, {"triangles", s.triangles}, {"welded_vertices", s.welded_vertices},
                      {"joints", s.joints}, {"ms", make_ms}}
                     .dump(2)
              << "\n";
  } else {
    std::cerr << "deepcut: wrote " << out << " (" << s.triangles << " triangles, " << s.welded_vertices
              << " vertices, " << s.joints << " joints)\n";
  }
  return 0;
}

}  // namespace deepcut::cli
