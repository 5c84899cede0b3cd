// SPDX-License-Identifier: MIT
#include "bench_cases.h"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vtkClipClosedSurface.h>
#include <vtkClipPolyData.h>
#include <vtkCylinder.h>
#include <vtkTransform.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPlaneCollection.h>
#include <vtkPolyData.h>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/ops/tear.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/softbody/simulation.h"
#include "deepcut/core/weld.h"
#include "deepcut/widgets/poly_data_bridge.h"

namespace deepcut::bench {
namespace {

struct Input {
  SurfaceMesh mesh;          // welded, with UVs, normals, joints, weights
  Adjacency adjacency;       // built once (the preprocessing)
  vtkSmartPointer<vtkPolyData> poly;  // the same mesh for VTK: split at seams, same arrays
  Plane plane;               // through the middle, slightly tilted
};

const Input& input(std::size_t triangles) {
  static std::map<std::size_t, std::unique_ptr<Input>> cache;
  auto& slot = cache[triangles];
  if (!slot) {
    CactusOptions options;
    options.target_triangles = triangles;
    Model model = make_cactus(options);
    slot = std::make_unique<Input>();
    slot->mesh = std::move(model.meshes[0].primitives[0].mesh);
    slot->adjacency = Adjacency::build(slot->mesh);
    slot->poly = to_poly_data(slot->mesh);
    const BoundingBox box = slot->mesh.bounds();
    slot->plane = {0.5f * (box.min + box.max) + glm::vec3(0.0f, 0.13f, 0.0f), glm::vec3(0.1f, 1.0f, 0.05f)};
  }
  return *slot;
}

// A fresh copy of the input as a session holds it after loading: with room to grow, so a timing
// is the operation's, not the first reallocation of every attribute array (memory_floor shows
// that cost), and with its adjacency (with the same room).
std::pair<SurfaceMesh, Adjacency> session_copy(const Input& in) {
  std::pair<SurfaceMesh, Adjacency> out{in.mesh, in.adjacency};
  SurfaceMesh& mesh = out.first;
  const std::size_t vertices = mesh.vertex_count() + mesh.vertex_count() / 8 + 4096;
  const std::size_t faces = mesh.face_slots() + mesh.face_slots() / 8 + 8192;
  mesh.reserve(vertices, faces);
  out.second.reserve(vertices, faces);
  return out;
}

// The session's spatial index over the input (built once, like the adjacency).
const TriangleGrid& grid_for(std::size_t triangles) {
  static std::map<std::size_t, TriangleGrid> grids;
  auto it = grids.find(triangles);
  if (it == grids.end()) {
    const Input& in = input(triangles);
    it = grids.emplace(triangles, TriangleGrid::build(in.mesh, in.mesh.positions())).first;
  }
  return it->second;
}

std::string size_name(std::size_t triangles) { return triangles >= 500000 ? "1M" : "25k"; }

void set_triangles(benchmark::State& state, const SurfaceMesh& mesh) {
  state.counters["triangles"] = static_cast<double>(mesh.face_count());
}

void bm_cut_ours(benchmark::State& state, std::size_t triangles, bool cap) {
  const Input& in = input(triangles);
  CutOptions options;
  options.cap = cap;
  for (auto _ : state) {
    state.PauseTiming();
    auto [mesh, adjacency] = session_copy(in);
    state.ResumeTiming();
    CutResult r = cut_mesh(mesh, mesh.positions(), in.plane, options);
    adjacency.apply(r.log);
    benchmark::DoNotOptimize(r.pieces.data());
    state.PauseTiming();
    mesh = SurfaceMesh();  // free outside the timed region
    adjacency = Adjacency();
    state.ResumeTiming();
  }
  set_triangles(state, in.mesh);
}

}  // namespace

vtkNew<vtkPlane> vtk_plane(const Plane& p) {
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(p.point.x, p.point.y, p.point.z);
  const glm::vec3 n = glm::normalize(p.normal);
  plane->SetNormal(n.x, n.y, n.z);
  return plane;
}

vtkNew<vtkCylinder> vtk_cylinder(const Cylinder& cyl) {
  vtkNew<vtkCylinder> cylinder;  // along y by default: rotate to the drill axis (z)
  cylinder->SetCenter(cyl.a.x, cyl.a.y, 0.0);
  cylinder->SetRadius(cyl.radius);
  cylinder->SetAxis(0.0, 0.0, 1.0);
  return cylinder;
}

namespace {

void bm_cut_vtk(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  auto plane = vtk_plane(in.plane);
  vtkNew<vtkClipPolyData> clip;
  clip->SetInputData(in.poly);
  clip->SetClipFunction(plane);
  clip->GenerateClippedOutputOn();
  for (auto _ : state) {
    clip->Modified();
    clip->Update();
    benchmark::DoNotOptimize(clip->GetOutput()->GetNumberOfCells());
  }
  set_triangles(state, in.mesh);
}

void bm_cut_cap_vtk(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  auto plane = vtk_plane(in.plane);
  vtkNew<vtkPlaneCollection> planes;
  planes->AddItem(plane);
  vtkNew<vtkClipClosedSurface> clip;
  clip->SetInputData(in.poly);
  clip->SetClippingPlanes(planes);
  clip->GenerateFacesOn();
  for (auto _ : state) {
    clip->Modified();
    clip->Update();
    benchmark::DoNotOptimize(clip->GetOutput()->GetNumberOfCells());
  }
  set_triangles(state, in.mesh);
}

// A hole through the trunk, front to back, at half its height (radius 3% of the model size).
// `radius` is a fraction of the model size.
Cylinder drill_cylinder(const Input& in, float radius = 0.03f) {
  const BoundingBox box = in.mesh.bounds();
  const glm::vec3 c = 0.5f * (box.min + box.max);
  const float r = radius * box.diagonal();
  return {{c.x, c.y, box.max.z + 1.0f}, {c.x, c.y, box.min.z - 1.0f}, r};
}

void bm_drill_ours(benchmark::State& state, std::size_t triangles, float radius = 0.03f) {
  const Input& in = input(triangles);
  const TriangleGrid& grid = grid_for(triangles);
  const Cylinder cyl = drill_cylinder(in, radius);
  PosedMesh posed;  // the input at bind pose, with its prebuilt grid
  posed.posed = in.mesh.positions();
  posed.grid = grid;
  posed.no_unpose = true;
  std::size_t touched = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto [mesh, adjacency] = session_copy(in);
    state.ResumeTiming();
    DrillResult r = drill_mesh(mesh, posed, cyl, {});
    adjacency.apply(r.log);
    benchmark::DoNotOptimize(r.log.size());
    touched = r.triangles_removed;
    state.PauseTiming();
    mesh = SurfaceMesh();
    adjacency = Adjacency();
    state.ResumeTiming();
  }
  state.counters["touched"] = static_cast<double>(touched);  // triangles the hole replaced
  set_triangles(state, in.mesh);
}

// The peer clips with an infinite cylinder: it neither bounds the depth, rounds the rim, nor
// blends the weights by the skin rule (it interpolates them linearly).
void bm_drill_vtk(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  auto cylinder = vtk_cylinder(drill_cylinder(in));
  vtkNew<vtkClipPolyData> clip;
  clip->SetInputData(in.poly);
  clip->SetClipFunction(cylinder);
  for (auto _ : state) {
    clip->Modified();
    clip->Update();
    benchmark::DoNotOptimize(clip->GetOutput()->GetNumberOfCells());
  }
  set_triangles(state, in.mesh);
}

// One scalpel stroke across the front of the trunk (a local edit: its cost follows the slit,
// with the session's spatial index).
void bm_tear(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  const TriangleGrid& grid = grid_for(triangles);
  const BoundingBox box = in.mesh.bounds();
  const glm::vec3 c = 0.5f * (box.min + box.max);
  const float h = box.max.y - box.min.y;
  // The blade cuts into the trunk's front (+z) face, sweeping sideways at a third of the height.
  const Blade start{{c.x - 0.08f * h, box.min.y + 0.33f * h, box.max.z + 0.5f}, {c.x - 0.08f * h, box.min.y + 0.33f * h, c.z}};
  const Blade end{{c.x + 0.08f * h, box.min.y + 0.35f * h, box.max.z + 0.5f}, {c.x + 0.08f * h, box.min.y + 0.35f * h, c.z}};
  PosedMesh at_rest;  // the session's posed mesh: its positions, bounds and grid
  at_rest.posed = in.mesh.positions();
  for (const glm::vec3& p : at_rest.posed) at_rest.bounds.add(p);
  at_rest.grid = grid;
  std::size_t points = 0, touched = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto [mesh, adjacency] = session_copy(in);
    PosedMesh posed = at_rest;  // a copy keeps no spare room: give it the session's (PosedModel)
    posed.posed.reserve(mesh.vertex_count() + mesh.vertex_count() / 8 + 1024);
    posed.grid.reserve(mesh.face_slots() + mesh.face_slots() / 8 + 2048, posed.posed.capacity());
    state.ResumeTiming();
    TearResult r = tear_mesh(mesh, posed, start, end);
    adjacency.apply(r.log);
    points = r.intersection_points;
    touched = 0;
    for (const Edit& e : r.log.edits) touched += std::holds_alternative<FaceRemoved>(e) ? 1 : 0;
    state.PauseTiming();
    posed = PosedMesh();
    mesh = SurfaceMesh();
    adjacency = Adjacency();
    state.ResumeTiming();
  }
  state.counters["intersection_points"] = static_cast<double>(points);
  state.counters["touched"] = static_cast<double>(touched);  // faces the stroke replaced (original or made)
  set_triangles(state, in.mesh);
}

float radius_for(const Input& in, std::size_t particles) {
  static std::map<std::pair<const Input*, std::size_t>, float> cache;
  auto [it, inserted] = cache.emplace(std::make_pair(&in, particles), 0.0f);
  if (inserted) it->second = radius_for_particle_count(in.mesh, in.mesh.positions(), particles);
  return it->second;
}

void bm_cluster(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  ClusterOptions options;
  options.radius = radius_for(input(25300), 224);  // the paper's 224-particle clustering
  std::size_t particles = 0;
  for (auto _ : state) {
    Clusters c = Clusters::build(in.mesh, in.mesh.positions(), options);
    particles = c.particle_count();
    benchmark::DoNotOptimize(particles);
  }
  state.counters["particles"] = static_cast<double>(particles);
  set_triangles(state, in.mesh);
}

// One frame: the spring step for every particle plus every vertex's displaced position.
void bm_softbody_step(benchmark::State& state, std::size_t triangles, std::size_t particles) {
  const Input& in = input(triangles);
  ClusterOptions options;
  options.radius = radius_for(input(25300), particles);
  const Clusters clusters = Clusters::build(in.mesh, in.mesh.positions(), options);
  SoftBodyState body = make_soft_body(clusters);
  const auto& posed = in.mesh.positions();
  const BoundingBox box = in.mesh.bounds();
  poke(body, clusters, posed, 0.5f * (box.min + box.max), glm::vec3(5.0f, 0.0f, 0.0f), 0.3f * box.diagonal());
  std::vector<glm::vec3> out(posed.size());
  for (auto _ : state) {
    step_soft_body(body, 1.0f / 90.0f);
    benchmark::DoNotOptimize(deformed_positions(body, clusters, posed, out));
  }
  state.counters["particles"] = static_cast<double>(clusters.particle_count());
  set_triangles(state, in.mesh);
}

// Weld + adjacency + spatial index on the mesh as a file stores it (every corner its own vertex where attributes
// differ), i.e. preprocessing without file parsing.
void bm_preprocess(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  // Un-weld at UV/normal seams the way glTF stores it: one vertex per distinct corner.
  static std::map<std::size_t, SurfaceMesh> split_cache;
  auto it = split_cache.find(triangles);
  if (it == split_cache.end()) {
    SurfaceMesh split;
    const auto& src = in.mesh;
    auto& j = split.vertex_attrs().add<glm::u16vec4>(attr::kJoints0);
    auto& w = split.vertex_attrs().add<glm::vec4>(attr::kWeights0);
    auto& uv = split.corner_attrs().add<glm::vec2>(attr::kUv0);
    auto& nrm = split.corner_attrs().add<glm::vec3>(attr::kNormal);
    const auto& sj = src.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
    const auto& sw = src.vertex_attrs().get<glm::vec4>(attr::kWeights0);
    const auto& suv = src.corner_attrs().get<glm::vec2>(attr::kUv0);
    const auto& sn = src.corner_attrs().get<glm::vec3>(attr::kNormal);
    src.for_each_face([&](FaceId f, const Triangle& t) {
      VertexId v[3];
      for (int k = 0; k < 3; ++k) {
        v[k] = split.add_vertex(src.position(t[k]));
        j[v[k].index] = sj[t[k].index];
        w[v[k].index] = sw[t[k].index];
      }
      const FaceId g = split.add_face(v[0], v[1], v[2]);
      for (int k = 0; k < 3; ++k) {
        uv[SurfaceMesh::corner(g, k)] = suv[SurfaceMesh::corner(f, k)];
        nrm[SurfaceMesh::corner(g, k)] = sn[SurfaceMesh::corner(f, k)];
      }
    });
    it = split_cache.emplace(triangles, std::move(split)).first;
  }
  for (auto _ : state) {
    state.PauseTiming();
    SurfaceMesh mesh = it->second;
    state.ResumeTiming();
    weld(mesh, {WeldKey::PositionAndSkin});  // the glTF importer's weld (io/gltf_read_mesh.cpp)
    Adjacency adjacency = Adjacency::build(mesh);
    TriangleGrid grid = TriangleGrid::build(mesh, mesh.positions());  // the drill's and preview's index
    benchmark::DoNotOptimize(adjacency.vertex_count());
    benchmark::DoNotOptimize(&grid);
    state.PauseTiming();
    mesh = SurfaceMesh();
    adjacency = Adjacency();
    state.ResumeTiming();
  }
  set_triangles(state, in.mesh);
}

// The floor: touching the mesh once (copying positions and triangles).
void bm_memory_floor(benchmark::State& state, std::size_t triangles) {
  const Input& in = input(triangles);
  for (auto _ : state) {
    std::vector<glm::vec3> p = in.mesh.positions();
    std::vector<Triangle> f = in.mesh.faces();
    benchmark::DoNotOptimize(p.data());
    benchmark::DoNotOptimize(f.data());
  }
  set_triangles(state, in.mesh);
}

std::size_t read_status_kb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stoul(line.substr(std::strlen(key)));
  return 0;
}

}  // namespace

void register_cases(bool with_1m) {
  std::vector<std::size_t> sizes = {25300};
  if (with_1m) sizes.push_back(1000000);
  for (std::size_t n : sizes) {
    const std::string s = size_name(n);
    const int iterations_hint = n >= 500000 ? 1 : 30;  // medians over 5 repetitions either way
    auto reg = [&](const std::string& name, auto fn) {
      benchmark::RegisterBenchmark(name.c_str(), fn)->Unit(benchmark::kMillisecond)->Iterations(iterations_hint);
    };
    reg("cut/ours/" + s, [n](benchmark::State& st) { bm_cut_ours(st, n, false); });
    reg("cut/vtkClipPolyData/" + s, [n](benchmark::State& st) { bm_cut_vtk(st, n); });
    reg("cut_cap/ours/" + s, [n](benchmark::State& st) { bm_cut_ours(st, n, true); });
    reg("cut_cap/vtkClipClosedSurface/" + s, [n](benchmark::State& st) { bm_cut_cap_vtk(st, n); });
    reg("preprocess/ours/" + s, [n](benchmark::State& st) { bm_preprocess(st, n); });
    reg("tear/ours/" + s, [n](benchmark::State& st) { bm_tear(st, n); });
    reg("drill/ours/" + s, [n](benchmark::State& st) { bm_drill_ours(st, n); });
    reg("drill/vtkClipPolyData+vtkCylinder/" + s, [n](benchmark::State& st) { bm_drill_vtk(st, n); });
    // The locality target: a hole touching at most 1000 triangles of the 1M model (926).
    if (n >= 500000) reg("drill_small/ours/" + s, [n](benchmark::State& st) { bm_drill_ours(st, n, 0.0062f); });
    // Model level, through apply_operation (model_cases.cpp).
    register_model_cases(n, s, iterations_hint);
    reg("cluster/ours/" + s, [n](benchmark::State& st) { bm_cluster(st, n); });
    reg("softbody_step_224/ours/" + s, [n](benchmark::State& st) { bm_softbody_step(st, n, 224); });
    reg("softbody_step_863/ours/" + s, [n](benchmark::State& st) { bm_softbody_step(st, n, 863); });
    reg("memory_floor/ours/" + s, [n](benchmark::State& st) { bm_memory_floor(st, n); });
  }
}

std::vector<Quoted> quoted_figures() {
  return {{"preprocess", 14480.0, "paper Table 1: preprocess for tear 13.6 s + drill 0.88 s (i7-7700HQ), quoted"},
          {"cut", 440.0, "paper Table 1: cut 0.44 s, 156 intersection points, quoted"},
          {"cut_cap", 440.0, "paper Table 1: cut 0.44 s (the paper does not cap), quoted"},
          {"tear", 95.0, "paper Table 1: tear 0.095 s, 26 intersection points, quoted"},
          {"drill", 200.0, "paper Table 1: drill 0.20 s, 27 intersection points, quoted; the VTK peer clips an infinite "
                           "cylinder: no depth bound, no round rim, linear weights"},
          {"cluster", 41300.0, "paper Table 1: soft-body clustering 41.3 s (224 particles), quoted"},
          {"softbody_step_224", 3.7, "paper Table 2: 1.5-3.7 ms per step with 224 particles (upper bound), quoted"},
          {"softbody_step_863", 6.7, "paper Table 2: 2.0-6.7 ms per step with 863 particles (upper bound), quoted"}};
}

MemoryReport measure_cut_memory() {
  int fds[2];
  MemoryReport report;
  if (pipe(fds) != 0) return report;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    CactusOptions options;
    options.target_triangles = 1000000;
    Model model = make_cactus(options);
    SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
    Adjacency adjacency = Adjacency::build(mesh);
    std::size_t bytes = mesh.faces().size() * sizeof(Triangle);
    for (const auto* set : {&mesh.vertex_attrs(), &mesh.corner_attrs(), &mesh.face_attrs()})
      for (const auto& name : set->names()) bytes += set->size() * set->base(name)->element_bytes();
    const BoundingBox box = mesh.bounds();
    const Plane plane{0.5f * (box.min + box.max), glm::vec3(0.1f, 1.0f, 0.05f)};
    { std::ofstream("/proc/self/clear_refs") << "5"; }  // reset the peak (VmHWM) to the current RSS
    const std::size_t before_kb = read_status_kb("VmRSS:");
    CutResult r = cut_mesh(mesh, mesh.positions(), plane);
    adjacency.apply(r.log);
    const std::size_t peak_kb = read_status_kb("VmHWM:");
    double out[4] = {bytes / 1048576.0, (peak_kb > before_kb ? peak_kb - before_kb : 0) / 1024.0, 0.0,
                     static_cast<double>(mesh.face_count())};
    out[2] = (out[0] + out[1]) / out[0];
    if (write(fds[1], out, sizeof(out)) != static_cast<ssize_t>(sizeof(out))) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  double in[4] = {0, 0, 0, 0};
  if (read(fds[0], in, sizeof(in)) == static_cast<ssize_t>(sizeof(in))) {
    report.mesh_mb = in[0];
    report.extra_peak_mb = in[1];
    report.ratio = in[2];
    report.triangles = static_cast<std::size_t>(in[3]);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return report;
}

}  // namespace deepcut::bench
