// SPDX-License-Identifier: MIT
/// @file generate/cactus_morph.cpp
/// The cactus's blend shapes. "arms_lift" moves each arm straight up, by nothing where it leaves
/// the trunk and by its full lift from the end of its bend to the tip (a smoothstep between), so
/// the part hidden in the trunk stays put. "bloom" scales the top of the trunk away from its
/// axis and lifts it, by nothing below its top dome and fully over the dome's upper half.

#include "generate/cactus_morph.h"

#include <algorithm>
#include <cmath>

#include "deepcut/core/attributes.h"
#include "geometry/predicates.h"

namespace deepcut::cactus_morph {
namespace {

/// How high the arms rise, relative to the cactus's height.
constexpr double kArmLift = 0.07;
/// How much the bloom widens the trunk's top (a scale factor of 1 + this) and lifts it
/// (relative to the dome's height).
constexpr double kBloomWidening = 0.45;
constexpr double kBloomLift = 0.35;

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

std::vector<glm::vec3> arms_lift(const std::vector<glm::vec3>& positions, const VertexOrigin& origin,
                                 const Shape& shape) {
  std::vector<glm::vec3> delta(positions.size(), glm::vec3(0.0f));
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (origin.limb[v] == 0) continue;
    const Shape::Arm& arm = shape.arms[origin.limb[v] - 1u];
    const double lift = kArmLift * shape.height * smoothstep(arm.start_s, arm.full_s, origin.spine_s[v]);
    delta[v] = glm::vec3(0.0f, static_cast<float>(lift), 0.0f);
  }
  return delta;
}

std::vector<glm::vec3> bloom(const std::vector<glm::vec3>& positions, const VertexOrigin& origin, const Shape& shape) {
  std::vector<glm::vec3> delta(positions.size(), glm::vec3(0.0f));
  const double full_y = shape.dome_base_y + 0.5 * shape.dome_height;
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (origin.limb[v] != 0) continue;
    const glm::dvec3 p(positions[v]);
    const double w = smoothstep(shape.dome_base_y, full_y, p.y);
    if (w == 0.0) continue;
    const glm::dvec3 d = w * (kBloomWidening * glm::dvec3(p.x, 0.0, p.z) +
                              glm::dvec3(0.0, kBloomLift * shape.dome_height, 0.0));
    delta[v] = glm::vec3(d);
  }
  return delta;
}

/// The normalised area-weighted normal of every slot at `positions` (zero for a slot no face
/// reaches or whose faces have no area).
std::vector<glm::vec3> slot_normals(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
                                    const NormalSlots& normals) {
  std::vector<glm::vec3> out(normals.count, glm::vec3(0.0f));
  const std::vector<Triangle>& faces = mesh.faces();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const glm::vec3& p0 = positions[faces[f][0].index];
    const glm::vec3 n = glm::cross(positions[faces[f][1].index] - p0, positions[faces[f][2].index] - p0);
    for (std::size_t k = 0; k < 3; ++k) out[normals.slots[3 * f + k]] += n;
  }
  for (glm::vec3& n : out) {
    const float len = glm::length(n);
    n = len > 0.0f ? n / len : glm::vec3(0.0f);
  }
  return out;
}

}  // namespace

void add_targets(SurfaceMesh& mesh, const VertexOrigin& origin, const Shape& shape, const NormalSlots& normals) {
  const std::vector<glm::vec3> positions = mesh.positions();
  const std::vector<glm::vec3> rest = slot_normals(mesh, positions, normals);
  const std::vector<glm::vec3> deltas[2] = {arms_lift(positions, origin, shape), bloom(positions, origin, shape)};
  for (int t = 0; t < 2; ++t) {
    std::vector<glm::vec3> morphed(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) morphed[v] = positions[v] + deltas[t][v];
    const std::vector<glm::vec3> moved = slot_normals(mesh, morphed, normals);
    mesh.vertex_attrs().add<glm::vec3>(attr::morph_position_name(t)).data() = deltas[t];
    auto& corner = mesh.corner_attrs().add<glm::vec3>(attr::morph_normal_name(t)).data();
    for (std::size_t c = 0; c < corner.size(); ++c) {
      const std::uint32_t s = normals.slots[c];
      corner[c] = moved[s] - rest[s];  // exactly zero where no face around the slot moved
    }
  }
}

void describe_targets(Mesh& mesh) {
  mesh.weights.assign(kTargetNames.size(), 0.0f);
  mesh.target_names.assign(kTargetNames.begin(), kTargetNames.end());
  std::string names;
  for (const std::string& name : kTargetNames) names += (names.empty() ? "\"" : ",\"") + name + "\"";
  mesh.extras_json = "{\"targetNames\":[" + names + "]}";
}

AnimationSampler weight_sampler(float seconds, float keys_per_second) {
  AnimationSampler sampler;
  sampler.components = static_cast<int>(kTargetNames.size());
  sampler.interpolation = Interpolation::Linear;
  const int intervals = std::max(2, static_cast<int>(std::lround(keys_per_second * seconds)));
  for (int i = 0; i <= intervals; ++i) {
    const float time = seconds * static_cast<float>(i) / static_cast<float>(intervals);
    sampler.input.push_back(i == intervals ? seconds : time);
    const int key = i == intervals ? 0 : i;  // the last key repeats the first: a seamless loop
    const double phase = geometry::kPi * key / intervals;
    const double lift = std::sin(phase), swell = std::sin(2.0 * phase);
    sampler.output.push_back(static_cast<float>(lift * lift));
    sampler.output.push_back(static_cast<float>(swell * swell));
  }
  return sampler;
}

}  // namespace deepcut::cactus_morph
