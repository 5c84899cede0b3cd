// SPDX-License-Identifier: MIT
#pragma once
// Shared by the operation fuzzers (fuzz_cut, fuzz_tear, fuzz_drill): the small rigged model they
// edit, parameters decoded from the fuzzer's bytes, and the invariant checks that abort on a
// violation. Each input is a short sequence (1-3 operations) on a fresh copy of the mesh, so the
// fuzzer also reaches operations on already cut, torn or drilled surface.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/model.h"
#include "deepcut/core/validate.h"

namespace deepcut::fuzz {

[[noreturn]] inline void finding(const char* target, const std::string& what) {
  std::fprintf(stderr, "fuzz_%s: %s\n", target, what.c_str());
  std::abort();
}

/// RiggedSimple: a closed skinned cylinder (96 vertices, 188 triangles, 2 joints).
inline const Model& base_model() {
  static const Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/RiggedSimple/RiggedSimple.gltf");
  return model;
}

inline std::size_t joint_count(const Model& model) { return model.skins.empty() ? 0 : model.skins[0].joints.size(); }

/// A float the operation sees: mostly a point of the model's box grown by half its size each way
/// (so most operations meet the surface), sometimes a raw value (NaN, Inf, 1e38, denormals).
inline float coordinate(FuzzedDataProvider& in, float lo, float hi) {
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) return in.ConsumeFloatingPoint<float>();
  const float t = in.ConsumeFloatingPointInRange<float>(-0.5f, 1.5f);
  return lo + t * (hi - lo);
}

inline glm::vec3 point(FuzzedDataProvider& in, const BoundingBox& box) {
  return {coordinate(in, box.min.x, box.max.x), coordinate(in, box.min.y, box.max.y), coordinate(in, box.min.z, box.max.z)};
}

inline glm::vec3 direction(FuzzedDataProvider& in) {
  return {coordinate(in, -1.0f, 1.0f), coordinate(in, -1.0f, 1.0f), coordinate(in, -1.0f, 1.0f)};
}

/// A positive length up to `scale`, or now and then a raw value.
inline float length(FuzzedDataProvider& in, float scale) {
  if (in.ConsumeIntegralInRange<int>(0, 15) == 0) return in.ConsumeFloatingPoint<float>();
  return in.ConsumeFloatingPointInRange<float>(0.0f, scale);
}

/// After every operation: the mesh is consistent (indices, attribute sizes, finite positions,
/// weights normalised, joints in the skin) and the adjacency updated from the log equals a rebuild.
inline void check(const char* target, const SurfaceMesh& mesh, const Adjacency& incremental, std::size_t joints) {
  try {
    validate_mesh(mesh, joints);
  } catch (const Error& e) {
    finding(target, std::string("invalid mesh after the operation: ") + e.what());
  }
  const Adjacency rebuilt = Adjacency::build(mesh);
  if (!(incremental == rebuilt)) finding(target, "incremental adjacency differs from a rebuild");
}

/// Runs `op` and turns anything but a clean refusal into a finding. @returns false if refused.
template <class Op>
bool run(const char* target, Op&& op) {
  try {
    op();
    return true;
  } catch (const Error& e) {
    if (!e.is_input_error()) finding(target, std::string("internal error: ") + e.what());
    return false;
  } catch (const std::exception& e) {
    finding(target, std::string("exception that is not deepcut::Error: ") + e.what());
  }
}

}  // namespace deepcut::fuzz
