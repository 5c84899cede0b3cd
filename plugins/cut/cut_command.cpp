// SPDX-License-Identifier: MIT
// The Plane tool's command line: deepcut cut (the studio side is cut_tool.cpp).
#include <nlohmann/json.hpp>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/formats.h"
#include "deepcut/plugins/operation_command.h"
#include "deepcut/plugins/tool_registry.h"

namespace deepcut::cli {
namespace {

using nlohmann::json;

// Vertices (welded) and triangles of every piece node's mesh.
json piece_list(const Model& model, const std::vector<int>& nodes) {
  json out = json::array();
  for (int n : nodes) {
    std::size_t v = 0, t = 0;
    const int m = model.nodes[n].mesh;
    if (m >= 0)
      for (const auto& p : model.meshes[m].primitives) {
        v += p.mesh.vertex_count();
        t += p.mesh.face_count();
      }
    out.push_back({{"node", model.nodes[n].name}, {"vertices", v}, {"triangles", t}});
  }
  return out;
}

int run_cut(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json", "--cap", "--components"}, {"-o", "--plane", "--keep", "--time", "--animation"});
  if (args.positionals().size() != 1) throw UsageError("cut needs exactly one MODEL");
  if (!args.has("-o")) throw UsageError("cut needs -o OUT (.glb or .gltf)");
  if (!args.has("--plane")) throw UsageError("cut needs --plane PX,PY,PZ,NX,NY,NZ");
  const auto p = args.vector("--plane", 6);
  CutOperation cut;
  cut.plane = {{p[0], p[1], p[2]}, {p[3], p[4], p[5]}};
  const std::string keep = args.value("--keep", "both");
  if (keep == "both") cut.options.keep = CutKeep::Both;
  else if (keep == "positive") cut.options.keep = CutKeep::Positive;
  else if (keep == "negative") cut.options.keep = CutKeep::Negative;
  else throw UsageError("--keep must be both, positive or negative");
  cut.options.cap = args.flag("--cap");
  cut.options.split_components = args.flag("--components");
  if (glm::length(cut.plane.normal) == 0.0f) throw Error(ErrorCode::InvalidArgument, "cut: the plane normal is zero");

  Model model = plugins::read_model(args.positionals()[0]);
  Operation op;
  op.params = cut;
  op.animation = pose_animation(args, model);
  op.time = static_cast<float>(args.number("--time", 0.0));
  double ms = 0.0;
  const ModelCutResult r =
      run_timed([&] { return cut_model(model, cut.plane, cut.options, op.animation, op.time); }, ms);
  finish_operation(args, model, op, r.status, ms,
                   {{"pieces", piece_list(model, r.piece_nodes)},
                    {"intersection_points", r.intersection_points},
                    {"rim_vertices", r.rim_vertices}},
                   "cut into " + count_of(r.piece_nodes.size(), "piece", "pieces"), "plane");
  return 0;
}

}  // namespace
}  // namespace deepcut::cli

namespace deepcut::plugins {

void describe_cut(ToolInfo& info) {
  info.id = "cut";
  info.title = "Plane";
  info.shortcut = "P";
  info.commands.push_back(
      {"cut",
       "cut MODEL -o OUT --plane PX,PY,PZ,NX,NY,NZ [--keep both|positive|negative] [--cap] [--components]\n"
       "    [--time T] [--animation I] [--json]",
       "cut every mesh by a plane (world space, pose at time T)", cli::run_cut});
}

}  // namespace deepcut::plugins
