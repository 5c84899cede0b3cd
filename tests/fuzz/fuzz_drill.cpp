// SPDX-License-Identifier: MIT
// libFuzzer target: drill_mesh with fuzzed cylinders (axis ends, radius), min_rim_edges, wall and
// tolerance, 1-3 drills in a row on RiggedSimple (the spatial index followed through the logs, or
// built afresh for each drill); drill_model posed at a fuzzed time now and then. Invariants after each: see
// fuzz_ops.h.
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/spatial_index.h"
#include "fuzz_ops.h"

using namespace deepcut;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Model& model = fuzz::base_model();
  const std::size_t joints = fuzz::joint_count(model);
  const BoundingBox box = model.meshes[0].primitives[0].mesh.bounds();
  const float scale = box.diagonal();
  const auto cylinder = [&] {
    Cylinder c;
    c.a = fuzz::point(in, box);
    c.b = fuzz::point(in, box);
    c.radius = fuzz::length(in, 0.5f * scale);
    return c;
  };
  const auto options = [&] {
    DrillOptions o;
    o.min_rim_edges = in.ConsumeIntegralInRange<int>(0, 96);
    o.wall = in.ConsumeBool();
    if (in.ConsumeBool()) o.relative_tolerance = fuzz::length(in, 0.05f);
    return o;
  };
  if (in.ConsumeIntegralInRange<int>(0, 7) == 0) {
    Model copy = model;
    const Cylinder c = cylinder();
    const DrillOptions o = options();
    const float time = in.ConsumeFloatingPointInRange<float>(-1.0f, 5.0f);
    if (fuzz::run("drill", [&] { drill_model(copy, c, o, 0, time); }))
      for (const Mesh& m : copy.meshes)
        for (const Primitive& p : m.primitives) fuzz::check("drill", p.mesh, Adjacency::build(p.mesh), joints);
    return 0;
  }
  SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
  Adjacency adj = Adjacency::build(mesh);
  std::vector<glm::vec3> posed = mesh.positions();
  const bool indexed = in.ConsumeBool();
  TriangleGrid grid = TriangleGrid::build(mesh, posed);
  const int steps = in.ConsumeIntegralInRange<int>(1, 3);
  for (int i = 0; i < steps && in.remaining_bytes() > 0; ++i) {
    const Cylinder c = cylinder();
    const DrillOptions o = options();
    DrillResult r;
    PosedMesh at = PosedMesh::at_positions(mesh, posed);
    if (indexed) at.grid = grid;
    if (!fuzz::run("drill", [&] { r = drill_mesh(mesh, at, c, o); })) continue;
    for (const auto& m : r.moved) posed[m.v.index] = m.posed;
    posed.insert(posed.end(), r.added_posed.begin(), r.added_posed.end());
    if (posed.size() != mesh.vertex_count()) fuzz::finding("drill", "added_posed does not cover the new vertices");
    grid.apply(r.log, posed);
    if (grid.face_count() != mesh.face_count()) fuzz::finding("drill", "the spatial index lost track of the faces");
    adj.apply(r.log);
    fuzz::check("drill", mesh, adj, joints);
  }
  return 0;
}
