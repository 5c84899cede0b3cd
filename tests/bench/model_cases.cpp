// SPDX-License-Identifier: MIT
// Model-level cases: the operations as the studio, `deepcut apply` and `deepcut cut|drill|tear`
// run them, through apply_operation on the whole skinned cactus Model (output pieces, nodes and
// the history record included), with the VTK peers measured in the same run on the same mesh.
//   cut_model       both sides kept, warm PosedModel (built before the timed region, as a session
//                   holds it), vs vtkClipPolyData producing both sides (GenerateClippedOutput on);
//   cut_model_cold  the same cut on the model as read, no PosedModel: posing inside the call, as
//                   `deepcut cut` pays it;
//   drill_model     the kernel case's hole (radius 3% of the size), warm, vs the VTK cylinder clip;
//   drill_model_small, drill_model_wall, tear_model: warm, vs the same call without a PosedModel
//                   ("uncached": the index built inside the call);
//   model_index     the PosedModel build itself (once per load or pose).
// Each iteration starts from a fresh copy of the model, made outside the timed region.
#include <map>
#include <string>

#include <benchmark/benchmark.h>
#include <vtkClipPolyData.h>
#include <vtkCylinder.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPolyData.h>

#include "bench_cases.h"
#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/widgets/poly_data_bridge.h"

namespace deepcut::bench {
namespace {

struct ModelInput {
  Model model;                        // the cactus as generated (what a reader gives)
  vtkSmartPointer<vtkPolyData> poly;  // its mesh for VTK: split at seams, same arrays
  BoundingBox box;                    // bind-pose bounds (the rest pose the operations use)
};

const ModelInput& model_input(std::size_t triangles) {
  static std::map<std::size_t, ModelInput> cache;
  auto it = cache.find(triangles);
  if (it == cache.end()) {
    CactusOptions options;
    options.target_triangles = triangles;
    ModelInput in;
    in.model = make_cactus(options);
    const SurfaceMesh& mesh = in.model.meshes[0].primitives[0].mesh;
    in.poly = to_poly_data(mesh);
    in.box = mesh.bounds();
    it = cache.emplace(triangles, std::move(in)).first;
  }
  return it->second;
}

void set_triangles(benchmark::State& state, const ModelInput& in) {
  state.counters["triangles"] = static_cast<double>(in.model.meshes[0].primitives[0].mesh.face_count());
}

// The kernel cases' plane (through the middle, slightly tilted), cylinder and blade.
Plane cut_plane(const ModelInput& in) {
  return {0.5f * (in.box.min + in.box.max) + glm::vec3(0.0f, 0.13f, 0.0f), glm::vec3(0.1f, 1.0f, 0.05f)};
}

Cylinder drill_cylinder(const ModelInput& in, float radius) {
  const glm::vec3 c = 0.5f * (in.box.min + in.box.max);
  return {{c.x, c.y, in.box.max.z + 1.0f}, {c.x, c.y, in.box.min.z - 1.0f}, radius * in.box.diagonal()};
}

Operation at_rest(OperationParams params) {
  Operation op;
  op.params = std::move(params);
  op.animation = -1;
  op.time = 0.0f;
  return op;
}

Operation cut_operation(const ModelInput& in) {
  CutOperation cut;
  cut.plane = cut_plane(in);
  return at_rest(cut);
}

Operation drill_operation(const ModelInput& in, float radius, bool wall) {
  DrillOperation drill;
  drill.cylinder = drill_cylinder(in, radius);
  drill.options.wall = wall;
  return at_rest(drill);
}

// One scalpel stroke across the front of the trunk (the kernel tear case's blade).
Operation tear_operation(const ModelInput& in) {
  const glm::vec3 c = 0.5f * (in.box.min + in.box.max);
  const float h = in.box.max.y - in.box.min.y, y0 = in.box.min.y + 0.33f * h, y1 = in.box.min.y + 0.35f * h;
  TearOperation tear;
  tear.start = {{c.x - 0.08f * h, y0, in.box.max.z + 0.5f}, {c.x - 0.08f * h, y0, c.z}};
  tear.end = {{c.x + 0.08f * h, y1, in.box.max.z + 0.5f}, {c.x + 0.08f * h, y1, c.z}};
  return at_rest(tear);
}

enum class Pose {
  Warm,  // a session's PosedModel, built before the timed region
  Cold   // no PosedModel: apply_operation poses the model inside the call
};

// Times apply_operation(model, op) on a fresh copy of the cactus each iteration.
void bm_apply(benchmark::State& state, std::size_t triangles, const Operation& op, Pose pose) {
  const ModelInput& in = model_input(triangles);
  std::size_t touched = 0;
  for (auto _ : state) {
    state.PauseTiming();
    Model model = in.model;
    PosedModel posed;
    // As the front ends hold it: a session reserves room to grow; `deepcut drill|tear` do too,
    // `deepcut cut` cuts the model as read.
    if (pose == Pose::Warm || !std::holds_alternative<CutOperation>(op.params)) reserve_for_operations(model);
    if (pose == Pose::Warm) posed = PosedModel::build(model, op.animation, op.time);
    state.ResumeTiming();
    const OperationResult r = pose == Pose::Warm ? apply_operation(model, op, posed) : apply_operation(model, op);
    benchmark::DoNotOptimize(r.status);
    if (const auto* drill = std::get_if<ModelDrillResult>(&r.result)) touched = drill->triangles_removed;
    state.PauseTiming();
    model = Model();  // freed outside the timed region
    posed = PosedModel();
    state.ResumeTiming();
  }
  if (touched > 0) state.counters["touched"] = static_cast<double>(touched);
  set_triangles(state, in);
}

// Runs `clip` (input and clip function set) once per iteration.
void time_clip(benchmark::State& state, vtkClipPolyData* clip, const ModelInput& in) {
  for (auto _ : state) {
    clip->Modified();
    clip->Update();
    benchmark::DoNotOptimize(clip->GetOutput()->GetNumberOfCells());
    benchmark::DoNotOptimize(clip->GetClippedOutput()->GetNumberOfCells());
  }
  set_triangles(state, in);
}

void bm_cut_vtk(benchmark::State& state, std::size_t triangles) {
  const ModelInput& in = model_input(triangles);
  auto plane = vtk_plane(cut_plane(in));
  vtkNew<vtkClipPolyData> clip;
  clip->SetInputData(in.poly);
  clip->SetClipFunction(plane);
  clip->GenerateClippedOutputOn();
  time_clip(state, clip, in);
}

// The peer clips with an infinite cylinder (no depth bound, no round rim, linear weights).
void bm_drill_vtk(benchmark::State& state, std::size_t triangles, float radius) {
  const ModelInput& in = model_input(triangles);
  auto cylinder = vtk_cylinder(drill_cylinder(in, radius));
  vtkNew<vtkClipPolyData> clip;
  clip->SetInputData(in.poly);
  clip->SetClipFunction(cylinder);
  time_clip(state, clip, in);
}

void bm_model_index(benchmark::State& state, std::size_t triangles) {
  const ModelInput& in = model_input(triangles);
  for (auto _ : state) {
    PosedModel index = PosedModel::build(in.model, 0, 1.0f);
    benchmark::DoNotOptimize(index.size());
    state.PauseTiming();
    index = PosedModel();
    state.ResumeTiming();
  }
  set_triangles(state, in);
}

}  // namespace

void register_model_cases(std::size_t triangles, const std::string& size, int iterations) {
  const std::size_t n = triangles;
  auto reg = [&](const std::string& name, auto fn) {
    benchmark::RegisterBenchmark(name.c_str(), fn)->Unit(benchmark::kMillisecond)->Iterations(iterations);
  };
  auto apply = [n](auto make_op, Pose pose) {
    return [n, make_op, pose](benchmark::State& st) { bm_apply(st, n, make_op(model_input(n)), pose); };
  };
  const auto cut = [](const ModelInput& in) { return cut_operation(in); };
  const auto drill = [](const ModelInput& in) { return drill_operation(in, 0.03f, false); };
  const auto drill_small = [](const ModelInput& in) { return drill_operation(in, 0.0062f, false); };
  const auto drill_wall = [](const ModelInput& in) { return drill_operation(in, 0.0062f, true); };
  const auto tear = [](const ModelInput& in) { return tear_operation(in); };
  reg("cut_model/ours/" + size, apply(cut, Pose::Warm));
  reg("cut_model/vtkClipPolyData/" + size, [n](benchmark::State& st) { bm_cut_vtk(st, n); });
  reg("cut_model_cold/ours/" + size, apply(cut, Pose::Cold));
  reg("cut_model_cold/vtkClipPolyData/" + size, [n](benchmark::State& st) { bm_cut_vtk(st, n); });
  reg("drill_model/ours/" + size, apply(drill, Pose::Warm));
  reg("drill_model/vtkClipPolyData+vtkCylinder/" + size, [n](benchmark::State& st) { bm_drill_vtk(st, n, 0.03f); });
  reg("drill_model_small/ours/" + size, apply(drill_small, Pose::Warm));
  reg("drill_model_small/uncached/" + size, apply(drill_small, Pose::Cold));
  reg("drill_model_wall/ours/" + size, apply(drill_wall, Pose::Warm));
  reg("drill_model_wall/uncached/" + size, apply(drill_wall, Pose::Cold));
  reg("tear_model/ours/" + size, apply(tear, Pose::Warm));
  reg("tear_model/uncached/" + size, apply(tear, Pose::Cold));
  reg("model_index/ours/" + size, [n](benchmark::State& st) { bm_model_index(st, n); });
}

}  // namespace deepcut::bench
