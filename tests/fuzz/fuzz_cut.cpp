// SPDX-License-Identifier: MIT
// libFuzzer target: cut_mesh with fuzzed planes (point, normal), keep side, caps, components and
// tolerance, 1-3 cuts in a row on RiggedSimple; the model-level cut_model (posed at a fuzzed
// time) now and then. Invariants after each: see fuzz_ops.h.
#include "deepcut/core/ops/cut.h"
#include "fuzz_ops.h"

using namespace deepcut;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Model& model = fuzz::base_model();
  const std::size_t joints = fuzz::joint_count(model);
  const bool whole_model = in.ConsumeIntegralInRange<int>(0, 7) == 0;
  if (whole_model) {
    Model copy = model;
    const BoundingBox box = copy.meshes[0].primitives[0].mesh.bounds();
    const Plane plane{fuzz::point(in, box), fuzz::direction(in)};
    CutOptions options;
    options.cap = in.ConsumeBool();
    options.split_components = in.ConsumeBool();
    const float time = in.ConsumeFloatingPointInRange<float>(-1.0f, 5.0f);
    if (fuzz::run("cut", [&] { cut_model(copy, plane, options, 0, time); }))
      for (const Mesh& m : copy.meshes)
        for (const Primitive& p : m.primitives) fuzz::check("cut", p.mesh, Adjacency::build(p.mesh), joints);
    return 0;
  }
  SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
  Adjacency adj = Adjacency::build(mesh);
  const BoundingBox box = mesh.bounds();
  const int steps = in.ConsumeIntegralInRange<int>(1, 3);
  for (int i = 0; i < steps && in.remaining_bytes() > 0; ++i) {
    const Plane plane{fuzz::point(in, box), fuzz::direction(in)};
    CutOptions options;
    options.keep = static_cast<CutKeep>(in.ConsumeIntegralInRange<int>(0, 2));
    options.cap = in.ConsumeBool();
    options.split_components = in.ConsumeBool();
    if (in.ConsumeBool()) options.relative_tolerance = fuzz::length(in, 0.1f);
    CutResult r;
    if (!fuzz::run("cut", [&] { r = cut_mesh(mesh, mesh.positions(), plane, options); })) continue;
    adj.apply(r.log);
    fuzz::check("cut", mesh, adj, joints);
  }
  return 0;
}
