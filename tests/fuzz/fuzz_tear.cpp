// SPDX-License-Identifier: MIT
// libFuzzer target: tear_mesh with fuzzed blade poses (handle and tip at start and end), width
// and tolerance, 1-3 tears in a row on RiggedSimple (consecutive tears join); tear_model posed at
// a fuzzed time now and then. Invariants after each: see fuzz_ops.h.
#include "deepcut/core/ops/tear.h"
#include "fuzz_ops.h"

using namespace deepcut;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Model& model = fuzz::base_model();
  const std::size_t joints = fuzz::joint_count(model);
  const BoundingBox box = model.meshes[0].primitives[0].mesh.bounds();
  const float scale = box.diagonal();
  const auto blade = [&] { return Blade{fuzz::point(in, box), fuzz::point(in, box)}; };
  if (in.ConsumeIntegralInRange<int>(0, 7) == 0) {
    Model copy = model;
    const Blade start = blade(), end = blade();
    TearOptions options;
    if (in.ConsumeBool()) options.width = fuzz::length(in, 0.2f * scale);
    const float time = in.ConsumeFloatingPointInRange<float>(-1.0f, 5.0f);
    if (fuzz::run("tear", [&] { tear_model(copy, start, end, options, 0, time); }))
      for (const Mesh& m : copy.meshes)
        for (const Primitive& p : m.primitives) fuzz::check("tear", p.mesh, Adjacency::build(p.mesh), joints);
    return 0;
  }
  SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
  Adjacency adj = Adjacency::build(mesh);
  const int steps = in.ConsumeIntegralInRange<int>(1, 3);
  for (int i = 0; i < steps && in.remaining_bytes() > 0; ++i) {
    const Blade start = blade(), end = blade();
    TearOptions options;
    if (in.ConsumeBool()) options.width = fuzz::length(in, 0.2f * scale);
    if (in.ConsumeBool()) options.relative_tolerance = fuzz::length(in, 0.1f);
    TearResult r;
    PosedMesh posed = PosedMesh::at_positions(mesh);
    if (!fuzz::run("tear", [&] { r = tear_mesh(mesh, posed, start, end, options); })) continue;
    adj.apply(r.log);
    fuzz::check("tear", mesh, adj, joints);
  }
  return 0;
}
