// SPDX-License-Identifier: MIT
// deepcut drill.
#include <chrono>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/history.h"

namespace deepcut::cli {

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

  Model model = read_gltf(args.positionals()[0]);
  Operation op;
  op.params = drill;
  op.animation = pose_animation(args, model);
  op.time = static_cast<float>(args.number("--time", 0.0));
  const auto t0 = std::chrono::steady_clock::now();
  const ModelDrillResult r = drill_model(model, drill.cylinder, drill.options, op.animation, op.time);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (r.status == OpStatus::Ok) record_operation(model, op);
  write_gltf(model, args.value("-o"));
  if (args.flag("--json")) {
    std::cout << nlohmann::json{{"status", to_string(r.status)},
                                {"holes", r.rim_vertices.size()},
                                {"rim_vertices", r.rim_vertices},
                                {"intersection_points", r.intersection_points},
                                {"triangles_removed", r.triangles_removed},
                                {"triangles_added", r.triangles_added},
                                {"wall_triangles", r.wall_triangles},
                                {"ms", ms}}
                     .dump(2)
              << "\n";
  } else {
    std::cerr << "deepcut: "
              << (r.status == OpStatus::Ok ? "drilled " + std::to_string(r.rim_vertices.size()) + " holes"
                                           : std::string("the drill misses the model; wrote it unchanged"))
              << " -> " << args.value("-o") << "\n";
  }
  return 0;
}

}  // namespace deepcut::cli
