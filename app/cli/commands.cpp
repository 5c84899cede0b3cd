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
#include "operation_report.h"

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

PositionalSpec model_argument() {
  return {"MODEL", "the model to read: a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh (loaded "
                   "unrigged: one root joint)"};
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

// What info reports on a model read from `path`.
struct InfoReport {
  const std::string& path;
  const Model& model;
  const ModelStats& stats;
  std::vector<ImportProblem> problems;
  std::size_t merged;  // glTF vertices the weld merged
};

// What reading repaired or dropped, then the checks of every primitive: info's report is the
// list, so it prints no stderr lines of its own.
std::vector<ImportProblem> info_problems(const Model& model, const ModelStats& s) {
  auto problems = model_problems(model);
  // A file with nothing to draw is a problem for every command that edits meshes.
  const bool reported = std::any_of(problems.begin(), problems.end(),
                                    [](const ImportProblem& p) { return p.kind == "no-triangles"; });
  if (s.meshes == 0)
    problems.push_back({"no-mesh", "the scene has no mesh", 1, {}});
  else if (s.triangles == 0 && !reported)
    problems.push_back({"no-triangles", "the mesh has no triangles", 1, {}});
  return problems;
}

std::size_t weld_merged(const Model& model) {
  std::size_t merged = 0;
  for (const auto& m : model.meshes)
    for (const auto& p : m.primitives) merged += p.welded_merged;
  return merged;
}

// The rest pose's bounding box, a point at the origin when empty.
std::pair<glm::vec3, glm::vec3> rest_bounds(const ModelStats& s) {
  if (s.bounds.empty()) return {glm::vec3(0.0f), glm::vec3(0.0f)};
  return {s.bounds.min, s.bounds.max};
}

// info --json's report, without load_ms.
json info_json(const InfoReport& r) {
  const ModelStats& s = r.stats;
  json anims = json::array();
  for (const auto& a : r.model.animations) anims.push_back({{"name", a.name}, {"duration", a.duration()}});
  const auto [lo, hi] = rest_bounds(s);
  return {{"file", r.path},
          {"nodes", s.nodes},
          {"meshes", s.meshes},
          {"primitives", s.primitives},
          {"vertices", s.gltf_vertices},
          {"welded_vertices", s.welded_vertices},
          {"weld_merged", r.merged},
          {"triangles", s.triangles},
          {"skins", s.skins},
          {"joints", s.joints},
          {"animations", s.animations},
          {"animation_clips", anims},
          {"morph_targets", morph_targets_json(r.model)},
          {"weight_channels", weight_channels_json(r.model)},
          {"materials", s.materials},
          {"textures", s.textures},
          {"images", s.images},
          {"boundary_edges", s.boundary_edges},
          {"nonmanifold_edges", s.nonmanifold_edges},
          {"seam_edges", s.seam_edges},
          {"components", s.components},
          {"bbox", {{"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}}},
          {"problems", problems_report(r.problems)}};
}

// info's text report.
void print_info(const InfoReport& r) {
  const ModelStats& s = r.stats;
  const auto [lo, hi] = rest_bounds(s);
  std::cout << r.path << "\n"
            << "  nodes " << s.nodes << ", meshes " << s.meshes << ", primitives " << s.primitives << "\n"
            << "  vertices " << s.gltf_vertices << " (glTF), " << s.welded_vertices << " welded (" << r.merged
            << " merged), triangles " << s.triangles << "\n"
            << "  skins " << s.skins << ", joints " << s.joints << ", materials " << s.materials
            << ", textures " << s.textures << ", images " << s.images << "\n"
            << "  animations " << s.animations;
  for (const auto& a : r.model.animations)
    std::cout << "\n    '" << a.name << "' " << std::setprecision(4) << a.duration() << " s";
  print_morphs(r.model);
  std::cout << "\n  edges: boundary " << s.boundary_edges << ", non-manifold " << s.nonmanifold_edges
            << ", seam " << s.seam_edges << "; components " << s.components << "\n"
            << "  bbox (rest pose) [" << lo.x << ", " << lo.y << ", " << lo.z << "] - [" << hi.x << ", "
            << hi.y << ", " << hi.z << "]\n"
            << "  problems: " << (r.problems.empty() ? "none" : std::to_string(r.problems.size())) << "\n";
  for (const auto& p : r.problems) std::cout << "    - " << p.message << "\n";
}

}  // namespace

const CommandSpec& info_command() {
  static const CommandSpec spec = with_synopsis(
      {"info",
       {model_argument()},
       "counts, edges, bounding box and problems of a model",
       "Reads MODEL as every command does (the weld included) and prints its nodes, meshes, primitives, "
       "vertices (glTF and welded), triangles, skins, joints, animations (names and durations in seconds), "
       "materials, textures, images, boundary, non-manifold and seam edges, connected components, the "
       "bounding box at the rest pose (world space, model units) and the problems found (what import "
       "dropped or repaired). It writes nothing.",
       {json_option("the same counts, plus load_ms,")},
       "deepcut info assets/cactus.glb --json",
       {}});
  return spec;
}

const CommandSpec& convert_command() {
  static const CommandSpec spec = with_synopsis(
      {"convert",
       {model_argument()},
       "import, weld and export (.gltf <-> .glb)",
       "Reads MODEL, welds the vertices glTF duplicated at UV seams and hard normals into one vertex (the "
       "seams stay in the per-corner attributes) and writes OUT as .glb or .gltf by its extension: it "
       "converts between the two, and turns a static mesh into a rigged glTF. Skins, animations, "
       "materials, textures and extensions are carried through; `deepcut info MODEL` lists what import "
       "drops or repairs.",
       [] {
         std::vector<OptionSpec> o = output_options();
         o.push_back(json_option("input, output, triangles, welded_vertices, read_ms and write_ms"));
         return o;
       }(),
       "deepcut convert assets/models/CesiumMan/CesiumMan.glb -o CesiumMan.gltf",
       {}});
  return spec;
}

const CommandSpec& make_cactus_command() {
  const CactusOptions defaults{};
  static const CommandSpec spec = with_synopsis(
      {"make-cactus",
       {},
       "write the project's rigged test cactus",
       "Generates the ribbed cactus the tests and benchmarks use (a trunk and two arms, each a closed "
       "surface on its own joint chain, with smooth skin weights and a looping sway animation) and writes "
       "it to OUT. The same options give the same file; assets/cactus.glb is its output with the defaults.",
       [&] {
         std::vector<OptionSpec> o = output_options();
         o.push_back({"--triangles", "N", "about how many triangles (a whole number, 1000 to 200000000)",
                      std::to_string(defaults.target_triangles), false, false});
         o.push_back({"--height", "H", "overall height, ground to the top of the trunk, in model units",
                      number_text(defaults.height), false, false});
         o.push_back(json_option("output, triangles, welded_vertices, joints and ms"));
         return o;
       }(),
       "deepcut make-cactus -o cactus-1m.glb --triangles 1000000",
       {}});
  return spec;
}

int run_info(const std::vector<std::string>& argv) {
  const Args args(argv, info_command());
  const std::string path = single_model(args, "info");
  const auto t0 = Clock::now();
  const Model model = plugins::read_model(path);
  const double load_ms = ms_since(t0);
  const ModelStats stats = compute_stats(model);
  const InfoReport report{path, model, stats, info_problems(model, stats), weld_merged(model)};
  if (args.flag("--json")) {
    json out = info_json(report);
    out["load_ms"] = load_ms;
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  print_info(report);
  return 0;
}

int run_convert(const std::vector<std::string>& argv) {
  const Args args(argv, convert_command());
  const std::string in = single_model(args, "convert");
  const std::string out = output_path(args, "convert");
  const ExportOptions export_opts = export_options(args);
  const auto t0 = Clock::now();
  const Model model = plugins::read_model(in);
  const double read_ms = ms_since(t0);
  print_problems(std::cerr, in, model.import_problems);
  const auto t1 = Clock::now();
  write_gltf(model, out, export_opts);
  const double write_ms = ms_since(t1);
  if (args.flag("--json")) {
    const ModelStats s = compute_stats(model);
    std::cout << json{{"input", in}, {"output", out}, {"triangles", s.triangles}, {"welded_vertices", s.welded_vertices},
                      {"problems", problems_report(model.import_problems)}, {"read_ms", read_ms}, {"write_ms", write_ms}}
                     .dump(2)
              << "\n";
  } else {
    std::cerr << "deepcut: wrote " << out << "\n";
  }
  return 0;
}

int run_make_cactus(const std::vector<std::string>& argv) {
  const Args args(argv, make_cactus_command());
  if (!args.positionals().empty()) throw UsageError("make-cactus takes no MODEL, only -o OUT");
  const std::string out = output_path(args, "make-cactus");
  const ExportOptions export_opts = export_options(args);
  CactusOptions options;
  const long long tris = args.integer("--triangles", static_cast<long long>(options.target_triangles));
  if (tris < 1000 || tris > 200000000)
    throw UsageError("--triangles must be a whole number between 1000 and 200000000");
  options.target_triangles = static_cast<std::size_t>(tris);
  options.height = static_cast<float>(args.number("--height", options.height));
  const auto t0 = Clock::now();
  const Model model = make_cactus(options);
  const double make_ms = ms_since(t0);
  write_gltf(model, out, export_opts);
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
