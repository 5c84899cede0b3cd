// SPDX-License-Identifier: MIT
// Cut and tear are exact at the pose they were made in, as the drill is: on every asset, at three
// poses (rest, the middle and the end of the first clip), every vertex of the output posed at
// that pose lies on the posed input surface within 1e-5 of the model size (a tear's lips excepted
// by their opening, measured along the tear normal), new cut vertices lie on the plane, new tear
// vertices on the swept quad, and no mesh edge crosses the swept quad at that pose.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/tear.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "fixtures.h"

namespace deepcut {
namespace {

constexpr double kExact = 1e-5;  // of the model size: the promise

struct PoseAt {
  int animation;
  float time;
  std::string name() const { return animation < 0 ? "rest" : "t=" + std::to_string(time); }
};

// Rest, and the middle and the end of the first clip when the model animates.
std::vector<PoseAt> three_poses(const Model& model) {
  std::vector<PoseAt> out = {{-1, 0.0f}};
  if (!model.animations.empty()) {
    const float d = model.animations[0].duration();
    out.push_back({0, 0.5f * d});
    out.push_back({0, d});
  }
  return out;
}

// Closest distance from p to triangle abc (double precision).
double point_triangle_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                               const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double nn = glm::dot(n, n);
  if (nn > 0.0) {
    const glm::dvec3 q = p - (glm::dot(p - a, n) / nn) * n;
    const glm::dvec3 e[3] = {b - a, c - b, a - c}, o[3] = {a, b, c};
    bool in = true;
    for (int k = 0; k < 3; ++k) in &= glm::dot(glm::cross(e[k], q - o[k]), n) >= 0.0;
    if (in) return glm::length(p - q);
  }
  const glm::dvec3 e[3] = {b - a, c - b, a - c}, o[3] = {a, b, c};
  double best = 1e300;
  for (int k = 0; k < 3; ++k) {
    const double ee = glm::dot(e[k], e[k]);
    const double s = ee > 0.0 ? std::clamp(glm::dot(p - o[k], e[k]) / ee, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(p - (o[k] + s * e[k])));
  }
  return best;
}

// The posed input: every instance at the pose, with its grid, and the model size there.
struct PosedInput {
  Model model;
  PosedModel posed;
  double size = 0.0;

  PosedInput(const Model& m, const PoseAt& pose)
      : model(m), posed(PosedModel::build(m, pose.animation, pose.time)) {
    BoundingBox box;
    for (const auto& [key, inst] : posed.instances()) box.add(inst.bounds);
    size = box.diagonal();
  }

  // Distance from `p` to the posed input surface, or `reach` when it is further than that.
  double distance(const glm::vec3& p, double reach) const {
    BoundingBox box;
    const glm::vec3 r(static_cast<float>(reach));
    box.add(p - r);
    box.add(p + r);
    double best = reach;
    for (const auto& [key, inst] : posed.instances()) {
      const SurfaceMesh& mesh = model.meshes[inst.mesh].primitives[inst.primitive].mesh;
      for (FaceId f : inst.grid.query_box(box)) {
        const Triangle& t = mesh.face(f);
        best = std::min(best, point_triangle_distance(glm::dvec3(p), glm::dvec3(inst.posed[t[0].index]),
                                                      glm::dvec3(inst.posed[t[1].index]),
                                                      glm::dvec3(inst.posed[t[2].index])));
      }
    }
    return best;
  }
};

// A random point of the posed instance's surface and its face normal.
void surface_point(const SurfaceMesh& mesh, const PosedMesh& inst, std::mt19937& rng, glm::vec3& p,
                   glm::vec3& n) {
  std::vector<FaceId> faces;
  mesh.for_each_face([&](FaceId f, const Triangle&) { faces.push_back(f); });
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (;;) {
    const Triangle& t =
        mesh.face(faces[std::uniform_int_distribution<std::size_t>(0, faces.size() - 1)(rng)]);
    const glm::vec3 a = inst.posed[t[0].index], b = inst.posed[t[1].index], c = inst.posed[t[2].index];
    const glm::vec3 cr = glm::cross(b - a, c - a);
    if (!(glm::length(cr) > 0.0f)) continue;
    p = test::point_in_triangle(a, b, c, u(rng), u(rng));
    n = glm::normalize(cr);
    return;
  }
}

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  glm::vec3 d;
  do d = {g(rng), g(rng), g(rng)};
  while (glm::length(d) < 1e-3f);
  return glm::normalize(d);
}

// A planar sweep through `p` across the surface: the blade stands along the normal `n` and moves
// along a random tangent (so the swept quad is one planar facet).
std::pair<Blade, Blade> sweep_through(const glm::vec3& p, const glm::vec3& n, double size,
                                      std::mt19937& rng) {
  glm::vec3 t = glm::cross(n, random_unit(rng));
  t = glm::length(t) > 1e-4f ? glm::normalize(t) : glm::normalize(glm::cross(n, glm::vec3(1, 0, 0)) + 1e-3f);
  const float s = static_cast<float>(size);
  const glm::vec3 from = p - 0.08f * s * t, to = p + 0.08f * s * t;
  return {Blade{from + 0.02f * s * n, from - 0.04f * s * n}, Blade{to + 0.02f * s * n, to - 0.04f * s * n}};
}

double quad_distance(const glm::vec3& p, const std::vector<std::array<glm::vec3, 3>>& quad) {
  double best = 1e300;
  for (const auto& t : quad)
    best = std::min(
        best, point_triangle_distance(glm::dvec3(p), glm::dvec3(t[0]), glm::dvec3(t[1]), glm::dvec3(t[2])));
  return best;
}

// Half-edges of `mesh` at `posed` crossing the interior of the swept quad: both ends further than
// `margin` off its plane on opposite sides, the crossing point further than `margin` inside.
std::size_t edges_crossing_quad(const SurfaceMesh& mesh, const std::vector<glm::vec3>& posed,
                                const std::vector<std::array<glm::vec3, 3>>& quad, double margin) {
  std::size_t n = 0;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 p(posed[t[k].index]), q(posed[t[(k + 1) % 3].index]);
      for (const auto& tri : quad) {
        const glm::dvec3 a(tri[0]), b(tri[1]), c(tri[2]);
        const glm::dvec3 nn = glm::normalize(glm::cross(b - a, c - a));
        const double dp = glm::dot(p - a, nn), dq = glm::dot(q - a, nn);
        if (!((dp > margin && dq < -margin) || (dp < -margin && dq > margin))) continue;
        const glm::dvec3 x = p + (dp / (dp - dq)) * (q - p);
        const glm::dvec3 e[3] = {b - a, c - b, a - c}, o[3] = {a, b, c};
        bool in = true;
        for (int j = 0; j < 3; ++j) in &= glm::dot(glm::cross(glm::normalize(e[j]), x - o[j]), nn) > margin;
        n += in;
      }
    }
  });
  return n;
}

// Largest distance of the posed vertices `which` of an instance to the posed input surface (the
// worst found so far is kept in `worst`).
double worst_distance(const PosedInput& input, const std::vector<glm::vec3>& posed,
                      const std::vector<VertexId>& which) {
  double worst = 0.0;
  for (VertexId v : which) worst = std::max(worst, input.distance(posed[v.index], 0.05 * input.size));
  return worst;
}

std::vector<VertexId> used_from(const SurfaceMesh& mesh, std::uint32_t first) {
  std::vector<bool> used(mesh.vertex_count(), false);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (VertexId v : t) used[v.index] = true;
  });
  std::vector<VertexId> out;
  for (std::uint32_t v = first; v < mesh.vertex_count(); ++v)
    if (used[v]) out.push_back(VertexId(v));
  return out;
}

struct Worst {
  double cut = 0.0, tear = 0.0;
};

// Cuts of each instance at the mesh level (its PosedMesh from the posed model, as cut_model
// hands it): every new vertex on the posed input surface and on the plane.
void check_cuts(const PosedInput& input, std::mt19937& rng, Worst& worst) {
  for (const auto& [key, inst] : input.posed.instances()) {
    const SurfaceMesh& source = input.model.meshes[inst.mesh].primitives[inst.primitive].mesh;
    if (source.face_count() == 0) continue;
    for (int i = 0; i < 3; ++i) {
      glm::vec3 p, n;
      surface_point(source, inst, rng, p, n);
      const Plane plane{p, random_unit(rng)};
      SurfaceMesh mesh = source;
      PosedMesh posed = inst;
      const CutResult r = cut_mesh(mesh, posed, plane, {});
      if (r.status != OpStatus::Ok) continue;
      const auto fresh = used_from(mesh, static_cast<std::uint32_t>(source.vertex_count()));
      const double off = worst_distance(input, posed.posed, fresh);
      worst.cut = std::max(worst.cut, off / input.size);
      EXPECT_LE(off, kExact * input.size)
          << "cut " << i << " of node " << key.first << ": a new vertex off the posed surface";
      double off_plane = 0.0;
      for (VertexId v : fresh)
        off_plane = std::max(off_plane, std::abs(glm::dot(glm::dvec3(posed.posed[v.index]) - glm::dvec3(p),
                                                          glm::dvec3(plane.normal))));
      EXPECT_LE(off_plane, kExact * input.size)
          << "cut " << i << " of node " << key.first << ": a rim vertex off the plane";
    }
  }
}

// The same cut through the model (pieces as nodes, rims snapped onto the plane): every vertex of
// every output instance, posed at the cut's pose, on the posed input surface.
void check_model_cut(const PosedInput& input, const PoseAt& pose, std::mt19937& rng) {
  const auto& [key, inst] = *input.posed.instances().begin();
  const SurfaceMesh& source = input.model.meshes[inst.mesh].primitives[inst.primitive].mesh;
  glm::vec3 p, n;
  surface_point(source, inst, rng, p, n);
  Model model = input.model;
  if (cut_model(model, Plane{p, random_unit(rng)}, {}, pose.animation, pose.time).status != OpStatus::Ok)
    return;
  const PosedModel after = PosedModel::build(model, pose.animation, pose.time, PoseDetail::Positions);
  for (const auto& [k, out] : after.instances()) {
    const SurfaceMesh& mesh = model.meshes[out.mesh].primitives[out.primitive].mesh;
    const double off = worst_distance(input, out.posed, used_from(mesh, 0));
    EXPECT_LE(off, kExact * input.size)
        << "cut_model: node " << k.first << " has a vertex off the posed surface";
  }
}

// Tears of each instance at the mesh level, without and with an opening: without, every new
// vertex on the posed input surface and the swept quad; with, every vertex moved from there only
// along the tear normal; in both, no edge crossing the swept quad.
void check_tears(const PosedInput& input, std::mt19937& rng, Worst& worst) {
  for (const auto& [key, inst] : input.posed.instances()) {
    const SurfaceMesh& source = input.model.meshes[inst.mesh].primitives[inst.primitive].mesh;
    if (source.face_count() == 0) continue;
    for (int i = 0; i < 3; ++i) {
      glm::vec3 p, n;
      surface_point(source, inst, rng, p, n);
      const auto [start, end] = sweep_through(p, n, input.size, rng);
      const auto quad = swept_quad_triangles(start, end);
      ASSERT_EQ(quad.size(), 2u);
      const glm::dvec3 normal = glm::normalize(
          glm::cross(glm::dvec3(quad[0][1] - quad[0][0]), glm::dvec3(quad[0][2] - quad[0][0])));
      SurfaceMesh closed = source, open = source;
      PosedMesh closed_pose = inst, open_pose = inst;
      TearOptions zero;
      zero.width = 0.0f;
      const TearResult r0 = tear_mesh(closed, closed_pose, start, end, zero);
      const TearResult r1 = tear_mesh(open, open_pose, start, end, {});
      ASSERT_EQ(r0.status, r1.status);
      if (r0.status != OpStatus::Ok) continue;
      const std::string what = "tear " + std::to_string(i) + " of node " + std::to_string(key.first);
      const auto fresh = used_from(closed, static_cast<std::uint32_t>(source.vertex_count()));
      const double off = worst_distance(input, closed_pose.posed, fresh);
      worst.tear = std::max(worst.tear, off / input.size);
      EXPECT_LE(off, kExact * input.size) << what << ": a new vertex off the posed surface";
      // On the quad within the tear's own snapping tolerance, as at rest.
      double off_quad = 0.0;
      for (VertexId v : fresh) off_quad = std::max(off_quad, quad_distance(closed_pose.posed[v.index], quad));
      EXPECT_LE(off_quad, (zero.relative_tolerance + kExact) * input.size)
          << what << ": a slit vertex off the swept quad";
      ASSERT_EQ(open.vertex_count(), closed.vertex_count());
      double sideways = 0.0;
      for (std::size_t v = 0; v < open.vertex_count(); ++v) {
        const glm::dvec3 d = glm::dvec3(open_pose.posed[v]) - glm::dvec3(closed_pose.posed[v]);
        sideways = std::max(sideways, glm::length(d - glm::dot(d, normal) * normal));
      }
      worst.tear = std::max(worst.tear, sideways / input.size);
      EXPECT_LE(sideways, kExact * input.size) << what << ": a lip moved off the tear normal";
      const double margin = 2.0 * zero.relative_tolerance * input.size;
      EXPECT_EQ(edges_crossing_quad(closed, closed_pose.posed, quad, margin), 0u) << what << " (closed)";
      EXPECT_EQ(edges_crossing_quad(open, open_pose.posed, quad, margin), 0u) << what << " (opened)";
    }
  }
}

TEST(ExactPose, cut_and_tear_at_three_poses_leave_every_vertex_on_the_posed_input_surface) {
  for (const auto& path : test::asset_models()) {
    const Model model = read_gltf(path);
    const std::string name = std::filesystem::path(path).stem().string();
    std::mt19937 rng(2026);
    for (const PoseAt& pose : three_poses(model)) {
      SCOPED_TRACE(name + " at " + pose.name());
      const PosedInput input(model, pose);
      Worst worst;
      check_cuts(input, rng, worst);
      if (::testing::Test::HasFatalFailure()) return;
      check_model_cut(input, pose, rng);
      check_tears(input, rng, worst);
      if (::testing::Test::HasFatalFailure()) return;
      std::printf("[ exact ] %-14s %-10s max off the posed surface: cut %.2e, tear %.2e of the size\n",
                  name.c_str(), pose.name().c_str(), worst.cut, worst.tear);
    }
  }
}

}  // namespace
}  // namespace deepcut
