// SPDX-License-Identifier: MIT
#include "operation_report.h"

#include "args.h"

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

json cut_report(const Model& model, const ModelCutResult& r) {
  return {{"pieces", piece_list(model, r.piece_nodes)},
          {"intersection_points", r.intersection_points},
          {"rim_vertices", r.rim_vertices}};
}

json tear_report(const ModelTearResult& r) {
  return {{"tear_vertices", r.tear_vertices},
          {"intersection_points", r.intersection_points},
          {"slits", r.slits},
          {"width", r.width},
          {"opening", r.opening}};
}

json drill_report(const DrillOperation& drill, const ModelDrillResult& r) {
  json report{{"holes", r.rim_vertices.size()},
              {"rim_vertices", r.rim_vertices},
              {"intersection_points", r.intersection_points},
              {"triangles_removed", r.triangles_removed},
              {"triangles_added", r.triangles_added},
              {"wall_triangles", r.wall_triangles},
              {"unwalled_holes", r.unwalled_holes}};
  // A wall asked for but some holes could not be closed: say so instead of staying silent.
  if (drill.options.wall && r.status == OpStatus::Ok && r.unwalled_holes > 0)
    report["wall_note"] =
        "no wall for " + std::to_string(r.unwalled_holes) + " of the " +
        count_of(r.rim_vertices.size(), "hole", "holes") +
        ": their rims join a boundary the model already had (an earlier hole, cut or tear without a "
        "wall) so the surface there was open before the drill, or their part was open already (an open sheet "
        "or a torn part gets tubes between its rims, never a cup to the end of the cylinder), or the surface "
        "passes through itself there more than twice";
  return report;
}

}  // namespace

json operation_report(const Model& model, const Operation& operation, const OperationResult& result,
                      const std::vector<ImportProblem>& run_problems) {
  json report;
  if (const auto* cut = std::get_if<ModelCutResult>(&result.result)) report = cut_report(model, *cut);
  if (const auto* tear = std::get_if<ModelTearResult>(&result.result)) report = tear_report(*tear);
  if (const auto* drill = std::get_if<ModelDrillResult>(&result.result))
    report = drill_report(std::get<DrillOperation>(operation.params), *drill);
  report["status"] = to_string(result.status);
  report["problems"] = problems_report(model.import_problems);
  for (const json& p : problems_report(run_problems)) report["problems"].push_back(p);
  return report;
}

json problems_report(const std::vector<ImportProblem>& problems) {
  json out = json::array();
  for (const auto& p : problems)
    out.push_back({{"kind", p.kind}, {"message", p.message}, {"count", p.count}, {"places", p.places}});
  return out;
}

void print_problems(std::ostream& out, const std::string& file, const std::vector<ImportProblem>& problems) {
  // A file name or message with a control character (a newline) must not break the one-line rule.
  auto one_line = [](std::string text) {
    for (char& c : text)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = ' ';
    return text;
  };
  for (const auto& p : problems) out << "deepcut: " << one_line(file) << ": " << one_line(p.message) << " [" << p.kind << "]\n";
}

std::string operation_summary(const OperationResult& result) {
  if (const auto* r = std::get_if<ModelCutResult>(&result.result))
    return "cut into " + count_of(r->piece_nodes.size(), "piece", "pieces");
  if (const auto* r = std::get_if<ModelTearResult>(&result.result))
    return "tore " + count_of(r->slits, "slit", "slits") + ", " +
           count_of(r->tear_vertices, "tear vertex", "tear vertices") + ", opening " + std::to_string(r->opening) +
           " (asked " + std::to_string(r->width) + ")";
  const auto& r = std::get<ModelDrillResult>(result.result);
  return "drilled " + count_of(r.rim_vertices.size(), "hole", "holes");
}

const char* operation_tool(const Operation& operation) {
  if (std::holds_alternative<CutOperation>(operation.params)) return "plane";
  if (std::holds_alternative<TearOperation>(operation.params)) return "blade";
  return "drill";
}

}  // namespace deepcut::cli
