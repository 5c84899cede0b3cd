// SPDX-License-Identifier: MIT
#include "three_client.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "tools.h"

namespace deepcut::test {
namespace {

using nlohmann::json;
using Instance = std::pair<int, int>;  // (node, primitive)

std::string pose_three_command() { return "node " + quote(DEEPCUT_POSE_THREE_SCRIPT); }

std::string at(float time) {
  std::ostringstream s;
  s << "t = " << time << ": ";
  return s.str();
}

std::string vec(const glm::dvec3& v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

// Nodes reachable from the default scene's roots (what three.js puts in gltf.scene).
std::set<int> scene_nodes(const Model& model) {
  std::set<int> seen;
  std::vector<int> stack = model.root_nodes();
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (n < 0 || static_cast<std::size_t>(n) >= model.nodes.size() || !seen.insert(n).second) continue;
    stack.insert(stack.end(), model.nodes[std::size_t(n)].children.begin(), model.nodes[std::size_t(n)].children.end());
  }
  return seen;
}

// The project's mesh instances of the default scene.
std::set<Instance> project_instances(const Model& model) {
  std::set<Instance> out;
  for (int n : scene_nodes(model)) {
    const int mesh = model.nodes[std::size_t(n)].mesh;
    if (mesh < 0 || static_cast<std::size_t>(mesh) >= model.meshes.size()) continue;
    for (std::size_t p = 0; p < model.meshes[std::size_t(mesh)].primitives.size(); ++p) out.insert({n, int(p)});
  }
  return out;
}

struct PoseContext {
  const Model& model;
  const json& entry;  // the file's entry of pose_three's output
  const PosedModel& posed;
  const Pose& pose;  // the same pose: its morph weights name what was blended when they differ
  float time = 0.0f;
  double size = 0.0;  // the project's posed bounds diagonal at `time`
  double tolerance = 0.0;
};

std::vector<float> weights_of(const Pose& pose, int node) {
  return static_cast<std::size_t>(node) < pose.weights.size() ? pose.weights[std::size_t(node)] : std::vector<float>{};
}

// Compares instance `i` of three's entry at pose `pose`; returns its largest corner distance.
double compare_instance(const PoseContext& c, std::size_t i, const json& pose, ThreeComparison& out) {
  const json& inst = c.entry["instances"][i];
  const int node = inst["node"].get<int>(), prim = inst["primitive"].get<int>();
  const std::string name = "node " + std::to_string(node) + " primitive " + std::to_string(prim);
  const PosedMesh* pm = c.posed.find(node, prim);
  if (!pm) {
    out.problems.push_back(at(c.time) + "three.js draws " + name + ", which the project does not pose");
    return 0.0;
  }
  const SurfaceMesh& mesh = c.model.meshes[std::size_t(pm->mesh)].primitives[std::size_t(prim)].mesh;
  const auto indices = inst["indices"].get<std::vector<std::size_t>>();
  const auto positions = pose["positions"][i].get<std::vector<double>>();
  if (indices.size() != 3 * mesh.face_slots()) {
    out.problems.push_back(at(c.time) + name + ": three.js has " + std::to_string(indices.size() / 3) +
                           " triangles, the project " + std::to_string(mesh.face_slots()));
    return 0.0;
  }
  double worst = 0.0;
  std::size_t worst_corner = 0;
  for (std::size_t f = 0; f < mesh.face_slots(); ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t g = indices[3 * f + k];
      if (3 * g + 2 >= positions.size()) {
        out.problems.push_back(at(c.time) + name + ": three.js index " + std::to_string(g) + " is past its vertices");
        return worst;
      }
      const glm::dvec3 three(positions[3 * g], positions[3 * g + 1], positions[3 * g + 2]);
      const double d = glm::length(three - glm::dvec3(pm->posed[mesh.faces()[f][k].index]));
      if (d > worst) worst = d, worst_corner = 3 * f + k;
    }
  out.corners += 3 * mesh.face_slots();
  if (worst > c.tolerance) {
    const std::size_t g = indices[worst_corner];
    out.problems.push_back(at(c.time) + name + ": glTF vertex " + std::to_string(g) + " is " +
                           std::to_string(worst / c.size) + " of the model size apart (three.js " +
                           vec({positions[3 * g], positions[3 * g + 1], positions[3 * g + 2]}) + ", project " +
                           vec(glm::dvec3(pm->posed[mesh.faces()[worst_corner / 3][worst_corner % 3].index])) +
                           "; morph weights: three.js " + pose["weights"][i].dump() + ", project " +
                           json(weights_of(c.pose, node)).dump() + ")");
  }
  return worst;
}

// Compares one pose (three's `pose`, the project's at the same time).
void compare_pose(const Model& model, const json& entry, const json& pose, int animation, float tolerance,
                  ThreeComparison& out) {
  const float time = pose["time"].get<float>();
  const PosedModel posed = PosedModel::build(model, animation, time, PoseDetail::Positions);
  const std::set<Instance> wanted = project_instances(model);
  BoundingBox bounds;
  for (const Instance& inst : wanted)
    if (const PosedMesh* pm = posed.find(inst.first, inst.second)) bounds.add(pm->bounds);
  const double size = bounds.diagonal();
  const Pose sampled = animation < 0 ? rest_pose(model) : sample_pose(model, animation, time);
  const PoseContext c{model, entry, posed, sampled, time, size, size * double(tolerance)};

  std::set<Instance> drawn;
  double worst = 0.0;
  for (std::size_t i = 0; i < entry["instances"].size(); ++i) {
    const json& inst = entry["instances"][i];
    drawn.insert({inst["node"].get<int>(), inst["primitive"].get<int>()});
    worst = std::max(worst, compare_instance(c, i, pose, out));
  }
  for (const Instance& inst : wanted)
    if (!drawn.count(inst))
      out.problems.push_back(at(time) + "three.js does not draw node " + std::to_string(inst.first) + " primitive " +
                             std::to_string(inst.second));
  out.instances = drawn.size();
  if (c.size > 0.0) out.worst = std::max(out.worst, float(worst / c.size));

  const auto tmin = pose["min"].get<std::vector<double>>(), tmax = pose["max"].get<std::vector<double>>();
  for (int a = 0; a < 3 && !bounds.empty(); ++a)
    if (std::abs(tmin[std::size_t(a)] - double(bounds.min[a])) > c.tolerance ||
        std::abs(tmax[std::size_t(a)] - double(bounds.max[a])) > c.tolerance) {
      out.problems.push_back(at(time) + "bounds differ: three.js " + vec({tmin[0], tmin[1], tmin[2]}) + " - " +
                             vec({tmax[0], tmax[1], tmax[2]}) + ", project " + vec(glm::dvec3(bounds.min)) + " - " +
                             vec(glm::dvec3(bounds.max)));
      break;
    }
}

// Compares three's entry for `request` with the project's posing of the same file.
ThreeComparison compare_entry(const ThreePoseRequest& request, const json& entry, float tolerance) {
  ThreeComparison out;
  out.file = request.file;
  if (entry.contains("error")) {
    out.problems.push_back("three.js cannot read it: " + entry["error"].get<std::string>());
    return out;
  }
  Model model;
  try {
    model = read_gltf(request.file, ImportOptions{/*weld=*/false});
  } catch (const std::exception& e) {
    out.problems.push_back(std::string("the project cannot read it: ") + e.what());
    return out;
  }
  if (entry["animations"].size() != model.animations.size())
    out.problems.push_back("three.js has " + std::to_string(entry["animations"].size()) + " animations, the project " +
                           std::to_string(model.animations.size()));
  for (std::size_t a = 0; a < std::min(entry["animations"].size(), model.animations.size()); ++a) {
    const double three = entry["animations"][a]["duration"].get<double>(), ours = model.animations[a].duration();
    if (std::abs(three - ours) > 1e-6 * std::max(1.0, three))
      out.problems.push_back("animation " + std::to_string(a) + " lasts " + std::to_string(three) + " s in three.js, " +
                             std::to_string(ours) + " s in the project");
  }
  for (const json& pose : entry["poses"]) {
    try {
      compare_pose(model, entry, pose, request.animation, tolerance, out);
    } catch (const std::exception& e) {
      out.problems.push_back(at(pose["time"].get<float>()) + "the project cannot pose it: " + e.what());
    }
  }
  return out;
}

}  // namespace

std::string three_unavailable() {
  const RunResult r = run_command(pose_three_command() + " --check");
  if (r.exit_code == 0) return "";
  return "three.js posing unavailable (install node and run bash scripts/deps.sh): " +
         (r.err.empty() ? std::string("node not found") : r.err.substr(0, r.err.find('\n')));
}

ThreePoseRequest two_times_of_first_clip(const std::string& file, bool unit_rotations) {
  const Model model = read_gltf(file, ImportOptions{/*weld=*/false});
  if (model.animations.empty()) return {file, -1, {0.0f}, unit_rotations};
  const float duration = model.animations[0].duration();
  return {file, 0, {0.37f * duration, 0.81f * duration}, unit_rotations};
}

std::vector<ThreeComparison> compare_with_three(const std::vector<ThreePoseRequest>& requests, float tolerance) {
  json batch = json::array();
  for (const auto& r : requests) batch.push_back(
        {{"file", r.file}, {"animation", r.animation}, {"times", r.times}, {"unit_rotations", r.unit_rotations}});
  const std::string dir = temp_dir("three");
  const std::string request_file = dir + "/request.json";
  std::ofstream(request_file) << batch.dump();
  const RunResult run = run_command(pose_three_command() + " --request " + quote(request_file));
  std::filesystem::remove_all(dir);

  std::vector<ThreeComparison> out;
  json result;
  try {
    result = json::parse(run.out);
  } catch (const std::exception&) {
    for (const auto& r : requests)
      out.push_back({r.file, {"pose_three.mjs gave no JSON (exit " + std::to_string(run.exit_code) + "): " + run.err}});
    return out;
  }
  for (std::size_t i = 0; i < requests.size(); ++i) {
    if (i >= result.size()) {
      out.push_back({requests[i].file, {"pose_three.mjs gave no entry for it"}});
      continue;
    }
    out.push_back(compare_entry(requests[i], result[i], tolerance));
  }
  return out;
}

}  // namespace deepcut::test
