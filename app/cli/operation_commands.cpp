// SPDX-License-Identifier: MIT
// The rows of operation_commands(): each operation's flags, read into the parameters a history
// file holds (ops/operation.h). The checks that need no flag syntax are core's (check_operation).
#include <algorithm>
#include <cmath>
#include <limits>

#include "operation_command.h"

namespace deepcut::cli {
namespace {

CutOperation parse_cut(const Args& args) {
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
  return cut;
}

// Without --width the tear gets its blade's default width written in, so the export's history
// records the width used.
TearOperation parse_tear(const Args& args) {
  const auto s = args.vector("--blade-start", 6);
  const auto e = args.vector("--blade-end", 6);
  const auto check_range = [](const char* name, const std::vector<double>& values) {
    for (const double v : values)
      if (std::abs(v) > double(std::numeric_limits<float>::max()))
        throw UsageError(std::string(name) + ": a coordinate beyond 3.4e38 overflows single precision");
  };
  check_range("--blade-start", s);
  check_range("--blade-end", e);
  TearOperation tear;
  tear.start = {glm::vec3(s[0], s[1], s[2]), glm::vec3(s[3], s[4], s[5])};
  tear.end = {glm::vec3(e[0], e[1], e[2]), glm::vec3(e[3], e[4], e[5])};
  if (args.has("--width")) {
    const double w = args.number("--width", 0.0);
    if (w < 0.0) throw UsageError("--width must be >= 0");
    tear.options.width = static_cast<float>(w);
  } else if (const float w = resolved_tear_width(tear.start, tear.end, tear.options); std::isfinite(w)) {
    tear.options.width = w;
  }
  return tear;
}

DrillOperation parse_drill(const Args& args) {
  const auto a = args.vector("--axis", 6);
  DrillOperation drill;
  drill.cylinder.a = {a[0], a[1], a[2]};
  drill.cylinder.b = {a[3], a[4], a[5]};
  drill.cylinder.radius = static_cast<float>(args.number("--radius", 0.0));
  const double edges = args.number("--min-rim-edges", drill.options.min_rim_edges);
  if (edges != std::floor(edges)) throw UsageError("--min-rim-edges must be a whole number");
  // Out of range: check_operation names the range (an int holds every value it could refuse).
  drill.options.min_rim_edges = static_cast<int>(std::clamp(edges, double(std::numeric_limits<int>::min()),
                                                            double(std::numeric_limits<int>::max())));
  drill.options.wall = args.flag("--wall");
  return drill;
}

// An operation command's help and arguments: MODEL, -o OUT, its own options, the pose options
// and --json, in that order.
CommandSpec operation_spec(const std::string& name, const std::string& summary, const std::string& details,
                           const std::vector<OptionSpec>& own, const std::string& json_keys, const std::string& example) {
  std::vector<OptionSpec> options = output_options();
  options.insert(options.end(), own.begin(), own.end());
  for (const OptionSpec& o : pose_options()) options.push_back(o);
  options.push_back(json_option(json_keys));
  return with_synopsis({name,
                        {{"MODEL", "the model to edit: a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh"}},
                        summary,
                        details,
                        options,
                        example,
                        {}});
}

CommandSpec cut_spec() {
  return operation_spec(
      "cut", "cut every mesh by a plane (world space, pose at time T)",
      "The plane is placed against the model as posed at --time (animation --animation); every crossed edge "
      "is split once, shared by its two faces, and the new vertices get UVs, normals, tangents and colours "
      "interpolated per corner and skin weights by the influence rule (at most as many influences as the "
      "primitive carries, merged by joint, largest first, renormalised). The edit lands in bind space, so "
      "the pieces still animate. Each side becomes its own node and mesh, bound to the original skin. A plane "
      "that misses the model writes it unchanged (status no_intersection, exit 0).",
      {{"--plane", "PX,PY,PZ,NX,NY,NZ",
        "the cutting plane: a point P on it and its normal N (any length but 0), world space at the pose "
        "of --time/--animation, model units",
        "", true, false},
       {"--keep", "both|positive|negative",
        "which side to keep: positive keeps the side the normal N points to, negative the side behind the "
        "plane, both keeps both as separate pieces",
        "both", false, false},
       {"--cap", "",
        "close each rim loop of a closed piece with a flat cap (nested loops give caps with holes): planar "
        "UVs, outward normals, the rim's skin weights and a material of its own, \"Cut surface\"",
        "", false, false},
       {"--components", "", "split each side further into its connected parts, one node and mesh each", "", false,
        false}},
      "status, pieces (node, vertices, triangles of each), intersection_points, rim_vertices and ms",
      "deepcut cut assets/cactus.glb -o cut.glb --plane 0,5,0,0,1,0 --keep positive --cap --time 1.5");
}

CommandSpec tear_spec() {
  return operation_spec(
      "tear", "tear with a scalpel swept from one blade pose to another",
      "The blade is the segment from its handle H to its tip T. The quad it sweeps from the start pose to "
      "the end pose (H0 T0 T1 H1, folded along H0-T1 when not planar) is the tear surface: every mesh edge "
      "crossing it is split once, the vertices along the slit are duplicated so the lips come apart, and "
      "the lips are pushed apart along the quad's normal by --width, tapering to closed ends. No lip moves "
      "further than the longest edge of its triangles and no triangle flips, so a coarse mesh or a huge "
      "width opens less than asked (the report's opening says how far). Every layer the quad crosses is "
      "torn; a stroke that reaches an existing slit or border joins it. A quad that misses the model writes "
      "it unchanged (status no_intersection, exit 0).",
      {{"--blade-start", "HX,HY,HZ,TX,TY,TZ",
        "the blade where the stroke starts: its handle point H, then its tip point T, world space at the pose "
        "of --time/--animation, model units",
        "", true, false},
       {"--blade-end", "HX,HY,HZ,TX,TY,TZ", "the blade where the stroke ends: handle H, then tip T, as for "
                                            "--blade-start", "", true, false},
       {"--width", "W",
        "how far the lips open where the slit is widest, in model units (0: a closed slit)",
        "5% of the blade length", false, false}},
      "status, tear_vertices, intersection_points, slits, width (asked for), opening (achieved), ms and "
      "preprocess_ms",
      "deepcut tear assets/cactus.glb -o torn.glb --blade-start 0.6,7,-0.2,1.6,6.5,-0.8 "
      "--blade-end 1.2,8.5,0.2,2.2,7.9,-0.4");
}

CommandSpec drill_spec() {
  const DrillOptions defaults{};
  return operation_spec(
      "drill", "drill every mesh with a finite cylinder (world space, pose at time T)",
      "The cylinder, axis from A to B with radius R, removes the surface of every layer inside it: a hole "
      "through each wall the axis crosses between A and B (a blind hole when B lies inside the model), a "
      "notch where it only grazes a part. The rims lie on the cylinder and are round however coarse the "
      "mesh is; new vertices get UVs, normals, tangents and colours from their parent triangles and skin "
      "weights by the influence rule (at most as many influences as the primitive carries, merged by joint, "
      "largest first, renormalised). A hole that overlaps an older hole, a cut rim or a slit merges with it. "
      "A cylinder that misses writes the model unchanged (status no_intersection, exit 0); one that would "
      "remove every triangle of a node is refused (exit 2).",
      {{"--axis", "AX,AY,AZ,BX,BY,BZ",
        "the cylinder's axis from point A to point B (the hole ends at B), world space at the pose of "
        "--time/--animation, model units",
        "", true, false},
       {"--radius", "R", "the cylinder's radius in model units (> 0)", "", true, false},
       {"--min-rim-edges", "N",
        "fewest edges of each rim: the circle is sampled where N equal-angle rulings of the cylinder meet "
        "the crossed triangles (3 to 4096)",
        std::to_string(defaults.min_rim_edges), false, false},
       {"--wall", "",
        "line each hole with the part of the cylinder's surface inside the model (a tube from entry to exit "
        "rim, the bottom of a blind hole), with its own UVs, weights blended from the rims and the \"Cut "
        "surface\" material, so a closed model stays closed; holes whose rims join a boundary the model "
        "already had stay open and are counted in unwalled_holes",
        "", false, false}},
      "status, holes, rim_vertices, intersection_points, triangles_removed, triangles_added, wall_triangles, "
      "unwalled_holes, ms and preprocess_ms",
      "deepcut drill assets/cactus.glb -o drilled.glb --axis -2,5,0,2,5,0 --radius 0.3 --wall --time 1");
}

}  // namespace

const std::vector<OperationCommand>& operation_commands() {
  static const std::vector<OperationCommand> commands = {
      {cut_spec(), parse_cut},
      {tear_spec(), parse_tear},
      {drill_spec(), parse_drill},
  };
  return commands;
}

}  // namespace deepcut::cli
