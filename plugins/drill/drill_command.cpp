// SPDX-License-Identifier: MIT
// The Drill tool's command line: deepcut drill (the studio side is drill_tool.cpp).
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/model.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/plugins/formats.h"
#include "deepcut/plugins/operation_command.h"
#include "deepcut/plugins/tool_registry.h"

namespace deepcut::cli {

namespace {

// Live triangles drawn by each node (0 for nodes without a mesh).
std::vector<std::size_t> instance_triangles(const Model& model) {
  std::vector<std::size_t> out(model.nodes.size(), 0);
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    for (const auto& prim : model.meshes[static_cast<std::size_t>(mi)].primitives) out[ni] += prim.mesh.face_count();
  }
  return out;
}

int run_drill(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json", "--wall"},
                  {"-o", "--axis", "--radius", "--min-rim-edges", "--time", "--animation"});
  if (args.positionals().size() != 1) throw UsageError("drill needs exactly one MODEL");
  if (!args.has("-o")) throw UsageError("drill needs -o OUT (.glb or .gltf)");
  if (!args.has("--axis")) throw UsageError("drill needs --axis AX,AY,AZ,BX,BY,BZ");
  if (!args.has("--radius")) throw UsageError("drill needs --radius R");
  const auto a = args.vector("--axis", 6);
  DrillOperation drill;
  drill.cylinder.a = {a[0], a[1], a[2]};
  drill.cylinder.b = {a[3], a[4], a[5]};
  drill.cylinder.radius = static_cast<float>(args.number("--radius", 0.0));
  const double edges = args.number("--min-rim-edges", 32.0);
  if (edges != std::floor(edges)) throw UsageError("--min-rim-edges must be a whole number");
  if (edges < 3 || edges > 4096)
    throw Error(ErrorCode::InvalidArgument, "drill: --min-rim-edges must be between 3 and 4096");
  drill.options.min_rim_edges = static_cast<int>(edges);
  drill.options.wall = args.flag("--wall");
  if (!(drill.cylinder.radius > 0.0f))
    throw Error(ErrorCode::InvalidArgument, "drill: --radius must be positive");
  if (drill.cylinder.a == drill.cylinder.b)
    throw Error(ErrorCode::InvalidArgument, "drill: the axis end points A and B coincide");

  Model model = plugins::read_model(args.positionals()[0]);
  Operation op;
  op.params = drill;
  op.animation = pose_animation(args, model);
  op.time = static_cast<float>(args.number("--time", 0.0));
  const auto before = instance_triangles(model);
  double preprocess_ms = 0.0, ms = 0.0;
  PosedModel index = preprocess(model, op, preprocess_ms);
  const ModelDrillResult r = run_timed(
      [&] { return drill_model(model, index, drill.cylinder, drill.options, op.animation, op.time); }, ms);
  // A drill that swallows a whole instance is not a hole: refuse it rather than write an empty mesh.
  const auto after = instance_triangles(model);
  for (std::size_t ni = 0; ni < before.size(); ++ni)
    if (before[ni] > 0 && after[ni] == 0)
      throw Error(ErrorCode::InvalidArgument,
                  "the cylinder removes every triangle of node " + std::to_string(ni) +
                      (model.nodes[ni].name.empty() ? std::string() : " '" + model.nodes[ni].name + "'") +
                      " (" + std::to_string(before[ni]) + " triangles); use a smaller --radius");
  nlohmann::json report{{"holes", r.rim_vertices.size()},
                        {"rim_vertices", r.rim_vertices},
                        {"intersection_points", r.intersection_points},
                        {"triangles_removed", r.triangles_removed},
                        {"triangles_added", r.triangles_added},
                        {"wall_triangles", r.wall_triangles},
                        {"unwalled_holes", r.unwalled_holes},
                        {"preprocess_ms", preprocess_ms}};
  // --wall asked for but some holes could not be closed: say so instead of staying silent.
  if (drill.options.wall && r.status == OpStatus::Ok && r.unwalled_holes > 0) {
    const std::string note =
        "no wall for " + std::to_string(r.unwalled_holes) + " of the " +
        count_of(r.rim_vertices.size(), "hole", "holes") +
        ": their rims join a boundary the model already had (an earlier hole, cut or tear without a "
        "wall) so the surface there was open before the drill, or their part was open already (an open sheet "
        "or a torn part gets tubes between its rims, never a cup to the end of the cylinder), or the surface "
        "passes through itself there more than twice";
    report["wall_note"] = note;
    if (!args.flag("--json")) std::cerr << "deepcut: " << note << "\n";
  }
  finish_operation(args, model, op, r.status, ms, std::move(report),
                   "drilled " + count_of(r.rim_vertices.size(), "hole", "holes"), "drill");
  return 0;
}

}  // namespace
}  // namespace deepcut::cli

namespace deepcut::plugins {

void describe_drill(ToolInfo& info) {
  info.id = "drill";
  info.title = "Drill";
  info.shortcut = "D";
  info.commands.push_back(
      {"drill",
       "drill MODEL -o OUT --axis AX,AY,AZ,BX,BY,BZ --radius R [--min-rim-edges N] [--wall]\n"
       "    [--time T] [--animation I] [--json]",
       "drill every mesh with a finite cylinder (world space, pose at time T)", cli::run_drill});
}

}  // namespace deepcut::plugins
