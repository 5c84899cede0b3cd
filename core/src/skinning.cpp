// SPDX-License-Identifier: MIT
#include "deepcut/core/skinning.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/morph.h"
#include "deepcut/core/parallel.h"

namespace deepcut {
namespace {

// Vertices (or faces) per parallel chunk: the default cactus stays on one thread.
constexpr std::size_t kGrain = 16384;

// Key interval and local parameter for time t (clamped to the key range).
void find_key(const std::vector<float>& input, float t, std::size_t& i, float& s, float& dt) {
  const std::size_t n = input.size();
  if (n < 2 || t <= input.front()) {
    i = 0;
    s = 0.0f;
    dt = 0.0f;
    return;
  }
  if (t >= input.back()) {
    i = n - 2;
    s = 1.0f;
    dt = input[n - 1] - input[n - 2];
    return;
  }
  i = static_cast<std::size_t>(std::upper_bound(input.begin(), input.end(), t) - input.begin()) - 1;
  dt = input[i + 1] - input[i];
  s = dt > 0.0f ? (t - input[i]) / dt : 0.0f;
}

// Value `c` of key `k`; for cubic splines the value sits between its two tangents.
float value(const AnimationSampler& sm, std::size_t k, int c, int part = 1) {
  const int n = sm.components;
  if (sm.interpolation == Interpolation::CubicSpline) return sm.output[(3 * k + part) * n + c];
  return sm.output[k * n + c];
}

template <int N>
glm::vec<N, float> sample(const AnimationSampler& sm, float t, bool is_rotation) {
  glm::vec<N, float> out(0.0f);
  const std::size_t keys = sm.input.size();
  const std::size_t per_key = sm.interpolation == Interpolation::CubicSpline ? 3 : 1;
  if (keys == 0 || sm.output.size() < keys * per_key * N) return out;
  std::size_t i;
  float s, dt;
  find_key(sm.input, t, i, s, dt);
  if (keys == 1 || sm.interpolation == Interpolation::Step) {
    const std::size_t k = (keys > 1 && s >= 1.0f) ? i + 1 : i;
    for (int c = 0; c < N; ++c) out[c] = value(sm, k, c);
    return out;
  }
  if (sm.interpolation == Interpolation::Linear) {
    if (is_rotation) {
      const glm::quat a(value(sm, i, 3), value(sm, i, 0), value(sm, i, 1), value(sm, i, 2));
      const glm::quat b(value(sm, i + 1, 3), value(sm, i + 1, 0), value(sm, i + 1, 1), value(sm, i + 1, 2));
      const glm::quat q = glm::slerp(glm::normalize(a), glm::normalize(b), s);  // shortest path
      for (int c = 0; c < N; ++c) out[c] = q[c];  // glm stores x, y, z, w
      return out;
    }
    for (int c = 0; c < N; ++c) out[c] = value(sm, i, c) + s * (value(sm, i + 1, c) - value(sm, i, c));
    return out;
  }
  // Cubic Hermite spline (glTF 2.0 appendix C).
  const float s2 = s * s, s3 = s2 * s;
  const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  for (int c = 0; c < N; ++c)
    out[c] = h00 * value(sm, i, c) + h10 * dt * value(sm, i, c, 2) + h01 * value(sm, i + 1, c) +
             h11 * dt * value(sm, i + 1, c, 0);
  return out;
}

// Every one of the `n` components of a weights channel at time t (the glTF stride is the target
// count); `out` keeps its values when the sampler holds too few.
void sample_weights(const AnimationSampler& sm, float t, std::vector<float>& out) {
  const std::size_t n = out.size(), keys = sm.input.size();
  const bool cubic = sm.interpolation == Interpolation::CubicSpline;
  if (n == 0 || keys == 0 || sm.output.size() < keys * (cubic ? 3 : 1) * n) return;
  auto at = [&](std::size_t k, std::size_t c, std::size_t part) {
    return cubic ? sm.output[(3 * k + part) * n + c] : sm.output[k * n + c];
  };
  std::size_t i;
  float s, dt;
  find_key(sm.input, t, i, s, dt);
  if (keys == 1 || sm.interpolation == Interpolation::Step) {
    const std::size_t k = (keys > 1 && s >= 1.0f) ? i + 1 : i;
    for (std::size_t c = 0; c < n; ++c) out[c] = at(k, c, 1);
    return;
  }
  if (!cubic) {
    for (std::size_t c = 0; c < n; ++c) out[c] = at(i, c, 1) + s * (at(i + 1, c, 1) - at(i, c, 1));
    return;
  }
  const float s2 = s * s, s3 = s2 * s;
  const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  for (std::size_t c = 0; c < n; ++c)
    out[c] = h00 * at(i, c, 1) + h10 * dt * at(i, c, 2) + h01 * at(i + 1, c, 1) + h11 * dt * at(i + 1, c, 0);
}

}  // namespace

Pose rest_pose(const Model& model) {
  Pose pose;
  const auto n = model.nodes.size();
  pose.translation.resize(n);
  pose.rotation.resize(n);
  pose.scale.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    pose.translation[i] = model.nodes[i].translation;
    pose.rotation[i] = model.nodes[i].rotation;
    pose.scale[i] = model.nodes[i].scale;
  }
  pose.weights.resize(n);
  for (std::size_t i = 0; i < n; ++i) pose.weights[i] = default_morph_weights(model, static_cast<int>(i));
  return pose;
}

Pose sample_pose(const Model& model, int animation, float time) {
  Pose pose = rest_pose(model);
  if (animation < 0) return pose;
  if (static_cast<std::size_t>(animation) >= model.animations.size())
    throw Error(ErrorCode::InvalidArgument, "animation " + std::to_string(animation) + " does not exist (the model has " +
                                                std::to_string(model.animations.size()) + ")");
  const Animation& anim = model.animations[animation];
  for (const auto& ch : anim.channels) {
    if (ch.node < 0 || static_cast<std::size_t>(ch.node) >= model.nodes.size()) continue;
    if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= anim.samplers.size()) continue;
    const auto& sm = anim.samplers[ch.sampler];
    switch (ch.path) {
      case AnimationPath::Translation:
        pose.translation[ch.node] = sample<3>(sm, time, false);
        break;
      case AnimationPath::Scale:
        pose.scale[ch.node] = sample<3>(sm, time, false);
        break;
      case AnimationPath::Rotation: {
        const glm::vec4 q = sample<4>(sm, time, true);
        const glm::quat r = glm::normalize(glm::quat(q.w, q.x, q.y, q.z));
        pose.rotation[ch.node] = r;
        break;
      }
      case AnimationPath::Weights:
        sample_weights(sm, time, pose.weights[ch.node]);  // empty for a node without targets
        break;
    }
  }
  return pose;
}

Pose sample_pose(const Model& model, const PoseKey& key) {
  Pose pose = sample_pose(model, key.animation, key.time);
  for (const auto& [node, given] : key.weights) {
    if (node < 0 || static_cast<std::size_t>(node) >= pose.weights.size()) continue;
    std::vector<float>& w = pose.weights[static_cast<std::size_t>(node)];
    std::copy_n(given.begin(), std::min(given.size(), w.size()), w.begin());
  }
  return pose;
}

std::vector<glm::mat4> world_matrices(const Model& model, const Pose& pose) {
  const auto n = model.nodes.size();
  std::vector<glm::mat4> world(n, glm::mat4(1.0f));
  std::vector<char> done(n, 0);
  const auto parent = model.parents();
  // Iterative: resolve each node after its parent (guards against cycles in bad files).
  for (std::size_t start = 0; start < n; ++start) {
    std::vector<int> chain;
    int x = static_cast<int>(start);
    while (x >= 0 && !done[x] && chain.size() <= n) {
      chain.push_back(x);
      x = parent[x];
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const int i = *it;
      if (done[i]) continue;
      const Node& node = model.nodes[i];
      glm::mat4 local;
      if (node.matrix) {
        local = *node.matrix;
      } else {
        Node trs;
        trs.translation = pose.translation[i];
        trs.rotation = pose.rotation[i];
        trs.scale = pose.scale[i];
        local = trs.local_matrix();
      }
      const int p = parent[i];
      world[i] = (p >= 0 && done[p]) ? world[p] * local : local;
      done[i] = 1;
    }
  }
  return world;
}

std::vector<glm::mat4> joint_matrices(const Model& model, int skin, const std::vector<glm::mat4>& world) {
  const Skin& s = model.skins.at(static_cast<std::size_t>(skin));
  std::vector<glm::mat4> out(s.joints.size(), glm::mat4(1.0f));
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const int node = s.joints[j];
    if (node < 0 || static_cast<std::size_t>(node) >= world.size()) continue;
    const glm::mat4 ibm = j < s.inverse_bind_matrices.size() ? s.inverse_bind_matrices[j] : glm::mat4(1.0f);
    out[j] = world[node] * ibm;
  }
  return out;
}

namespace {

// Per-vertex skinning matrices, or an empty vector when the instance is not skinned.
std::vector<glm::mat4> vertex_matrices(const Model& model, int node, const SurfaceMesh& mesh,
                                       const std::vector<glm::mat4>& world) {
  const Node& n = model.nodes.at(static_cast<std::size_t>(node));
  if (n.skin < 0 || static_cast<std::size_t>(n.skin) >= model.skins.size()) return {};
  const auto joints = joint_matrices(model, n.skin, world);
  const SkinBlend blend(mesh, joints);
  if (!blend.skinned()) return {};
  std::vector<glm::mat4> out(mesh.vertex_count());
  parallel_for(out.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) out[v] = blend.matrix(v);
  });
  return out;
}

// The posed position of each vertex (posed_positions; posed_face_bounds measures the same values
// without storing them): morphed (MorphBlend), then moved by its skinning matrix (SkinBlend) or
// the node's, in one pass, without the morphed copy and the matrix per vertex in memory between
// them. Set up once per instance; the call is the per-vertex arithmetic, written only here.
class Poser {
 public:
  Poser(const Model& model, int node, const SurfaceMesh& mesh, const std::vector<glm::mat4>& world,
        const std::vector<float>& weights)
      : morph_(mesh, weights),
        rest_(mesh.positions()),
        rigid_(world.at(static_cast<std::size_t>(node))),
        joints_(skin_joints(model, node, world)),
        blend_(mesh, joints_),
        skinned_(blend_.skinned()) {}
  Poser(const Poser&) = delete;  // blend_ keeps joints_ by reference
  Poser& operator=(const Poser&) = delete;

  glm::vec3 operator()(std::size_t v) const { return posed(v, matrix(v)); }

  // The same in two steps, for callers that reuse a blended matrix: the vertex's matrix (its
  // skin's blend, else the node's), and the vertex posed by `m` (its matrix or an equal one).
  glm::mat4 matrix(std::size_t v) const { return skinned_ ? blend_.matrix(v) : rigid_; }
  glm::vec3 posed(std::size_t v, const glm::mat4& m) const {
    const glm::vec4 p(morph_.position(v, rest_[v]), 1.0f);
    return glm::vec3(m * p);
  }
  // Whether vertices u and v have one matrix for certain: the same joints and weights, bit for
  // bit (SkinBlend::matrix is a function of them alone), or no skin.
  bool same_matrix(std::size_t u, std::size_t v) const { return !skinned_ || blend_.same_influences(u, v); }

 private:
  // The joint matrices of the node's skin; none when it has no skin (the node's matrix poses it).
  static std::vector<glm::mat4> skin_joints(const Model& model, int node,
                                            const std::vector<glm::mat4>& world) {
    const Node& n = model.nodes.at(static_cast<std::size_t>(node));
    if (n.skin < 0 || static_cast<std::size_t>(n.skin) >= model.skins.size()) return {};
    return joint_matrices(model, n.skin, world);
  }

  const MorphBlend morph_;
  const std::vector<glm::vec3>& rest_;
  const glm::mat4& rigid_;
  const std::vector<glm::mat4> joints_;  // before blend_, which refers to it
  const SkinBlend blend_;
  const bool skinned_;
};

}  // namespace

std::vector<glm::vec3> posed_positions(const Model& model, int node, const SurfaceMesh& mesh,
                                       const std::vector<glm::mat4>& world) {
  return posed_positions(model, node, mesh, world, default_morph_weights(model, node));
}

std::vector<glm::vec3> posed_positions(const Model& model, int node, const SurfaceMesh& mesh,
                                       const std::vector<glm::mat4>& world, const std::vector<float>& weights) {
  const Poser poser(model, node, mesh, world, weights);
  std::vector<glm::vec3> out(mesh.positions().size());
  parallel_for(out.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) out[v] = poser(v);
  });
  return out;
}

std::vector<glm::vec3> posed_normals(const Model& model, int node, const SurfaceMesh& mesh,
                                     const std::vector<glm::mat4>& world) {
  return posed_normals(model, node, mesh, world, default_morph_weights(model, node));
}

std::vector<glm::vec3> posed_normals(const Model& model, int node, const SurfaceMesh& mesh,
                                     const std::vector<glm::mat4>& world, const std::vector<float>& weights) {
  const auto* normals = mesh.corner_attrs().find<glm::vec3>(attr::kNormal);
  if (!normals) return {};
  const MorphBlend morph(mesh, weights);
  const auto skin = vertex_matrices(model, node, mesh, world);
  std::vector<glm::vec3> out(normals->size());
  const glm::mat3 rigid = glm::transpose(glm::inverse(glm::mat3(world.at(static_cast<std::size_t>(node)))));
  parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const auto& t = mesh.face(FaceId(static_cast<std::uint32_t>(f)));
      for (int k = 0; k < 3; ++k) {
        const auto c = 3 * f + static_cast<std::size_t>(k);
        const glm::mat3 nm = skin.empty() ? rigid : glm::transpose(glm::inverse(glm::mat3(skin[t[k].index])));
        const glm::vec3 n = nm * morph.normal(c, (*normals)[c]);
        const float len = glm::length(n);
        out[c] = len > 0.0f ? n / len : n;
      }
    }
  });
  return out;
}

std::vector<glm::mat4> vertex_skin_matrices(const Model& model, int node, const SurfaceMesh& mesh,
                                            const std::vector<glm::mat4>& world) {
  auto out = vertex_matrices(model, node, mesh, world);
  if (out.empty()) out.assign(mesh.vertex_count(), world.at(static_cast<std::size_t>(node)));
  return out;
}

BoundingBox face_bounds(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions) {
  // Reduced over the pool: min and max give the same values in any order, bit for bit except the
  // sign of a zero (BoundingBox::add keeps the first of -0 and +0, so face order decides).
  return parallel_reduce(
      mesh.face_slots(), 65536, BoundingBox(),
      [&](std::size_t b, std::size_t e) {
        BoundingBox part;
        for (std::size_t f = b; f < e; ++f)
          if (!mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))))
            for (auto v : mesh.face(FaceId(static_cast<std::uint32_t>(f)))) part.add(positions[v.index]);
        return part;
      },
      [](BoundingBox acc, const BoundingBox& part) {
        acc.add(part);
        return acc;
      });
}

namespace {

// face_bounds(mesh, posed_positions(model, node, mesh, world, weights)) without the posed array:
// the vertices a live face uses are marked (a byte each), then posed and measured in one pass
// over the pool by the same Poser (the same value for each vertex). The bounds are equal in
// value, bit for bit except the sign of a zero: vertex order here, face order there, and
// BoundingBox::add keeps the first of -0 and +0. The array was 12 bytes a vertex of new memory,
// filled with zeros on the calling thread before the posing, and read again face by face.
BoundingBox posed_face_bounds(const Model& model, int node, const SurfaceMesh& mesh,
                              const std::vector<glm::mat4>& world, const std::vector<float>& weights) {
  const auto& rest = mesh.positions();
  const std::size_t nv = rest.size();
  std::unique_ptr<std::atomic<unsigned char>[]> used(new std::atomic<unsigned char>[nv]);
  parallel_for(nv, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) used[v].store(0, std::memory_order_relaxed);
  });
  parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f)
      if (!mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))))
        for (auto v : mesh.face(FaceId(static_cast<std::uint32_t>(f))))
          used[v.index].store(1, std::memory_order_relaxed);
  });
  const Poser poser(model, node, mesh, world, weights);
  return parallel_reduce(
      nv, kGrain, BoundingBox(),
      [&](std::size_t b, std::size_t e) {
        // A vertex skinned as the last one measured (most of a part bound to one joint) reuses
        // its blended matrix: the same matrix, the same position.
        BoundingBox part;
        glm::mat4 m(1.0f);
        std::size_t last = e;  // none yet
        for (std::size_t v = b; v < e; ++v) {
          if (!used[v].load(std::memory_order_relaxed)) continue;
          if (last == e || !poser.same_matrix(last, v)) m = poser.matrix(v);
          last = v;
          part.add(poser.posed(v, m));
        }
        return part;
      },
      [](BoundingBox acc, const BoundingBox& part) {
        acc.add(part);
        return acc;
      });
}

}  // namespace

BoundingBox world_bounds(const Model& model, const Pose& pose) {
  const auto world = world_matrices(model, pose);
  const std::vector<float> none;
  BoundingBox box;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const int m = model.nodes[i].mesh;
    if (m < 0 || static_cast<std::size_t>(m) >= model.meshes.size()) continue;
    for (const auto& prim : model.meshes[m].primitives) {
      const auto& weights = i < pose.weights.size() ? pose.weights[i] : none;
      box.add(posed_face_bounds(model, static_cast<int>(i), prim.mesh, world, weights));
    }
  }
  return box;
}

}  // namespace deepcut
