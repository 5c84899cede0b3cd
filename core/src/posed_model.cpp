// SPDX-License-Identifier: MIT
#include "deepcut/core/posed_model.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include "deepcut/core/errors.h"
#include "deepcut/core/morph.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_corner_normal.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/smallest_fit.h"
#include "parallel_beside.h"
#include "uninit_vector.h"

namespace deepcut {

namespace {

constexpr std::size_t kGrain = 16384;

// The box around two boxes (what the parallel passes over positions combine their parts with).
BoundingBox joined(BoundingBox acc, const BoundingBox& part) {
  acc.add(part);
  return acc;
}

// Bounds of every position, combined in chunk order (min / max are exact in any order).
constexpr std::size_t kBoundsGrain = 65536;
BoundingBox bounds_of(const std::vector<glm::vec3>& points) {
  return parallel_reduce(
      points.size(), kBoundsGrain, BoundingBox(),
      [&](std::size_t b, std::size_t e) {
        BoundingBox part;
        for (std::size_t i = b; i < e; ++i) part.add(points[i]);
        return part;
      },
      joined);
}

bool on_boundary(const BoundingBox& box, const glm::vec3& p) {
  for (int k = 0; k < 3; ++k)
    if (p[k] == box.min[k] || p[k] == box.max[k]) return true;
  return false;
}

// Poses vertex slots the same way posed_positions and the tear's frames do: the bind position
// morphed at the instance's weights, then the vertex's blended joint matrix when the instance is
// skinned, the node's world matrix otherwise.
class VertexPoser {
 public:
  explicit VertexPoser(const SurfaceMesh& mesh, const PosedMesh& inst)
      : p_(mesh.positions()),
        blend_(mesh, inst.joints),
        morph_(mesh, inst.weights),
        skinned_(blend_.skinned()),
        rigid_(inst.world) {}
  void operator()(std::size_t v, PosedMesh& inst, bool with_linear = true) const {
    const glm::mat4 m = skinned_ ? blend_.matrix(v) : rigid_;
    inst.posed[v] = glm::vec3(m * glm::vec4(morph_.position(v, p_[v]), 1.0f));
    if (with_linear) inst.linear[v] = glm::mat3(m);
  }
  // Poses vertices [b, e) into posed[v] and linear[v].
  void range(std::size_t b, std::size_t e, glm::vec3* posed, glm::mat3* linear) const {
    for (std::size_t v = b; v < e; ++v) {
      const glm::mat4 m = skinned_ ? blend_.matrix(v) : rigid_;
      posed[v] = glm::vec3(m * glm::vec4(morph_.position(v, p_[v]), 1.0f));
      linear[v] = glm::mat3(m);
    }
  }

 private:
  const std::vector<glm::vec3>& p_;
  SkinBlend blend_;
  MorphBlend morph_;
  bool skinned_;
  glm::mat4 rigid_;
};

const SurfaceMesh* instance_mesh(const Model& model, int node, int primitive) {
  if (node < 0 || static_cast<std::size_t>(node) >= model.nodes.size()) return nullptr;
  const int mi = model.nodes[static_cast<std::size_t>(node)].mesh;
  if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) return nullptr;
  const auto& prims = model.meshes[static_cast<std::size_t>(mi)].primitives;
  if (primitive < 0 || static_cast<std::size_t>(primitive) >= prims.size()) return nullptr;
  return &prims[static_cast<std::size_t>(primitive)].mesh;
}

}  // namespace

void reserve_for_operations(Model& model) {
  for (Mesh& mesh : model.meshes)
    for (Primitive& prim : mesh.primitives) {
      SurfaceMesh& m = prim.mesh;
      m.reserve(operation_vertex_room(m.vertex_count()), operation_face_room(m.face_slots()));
    }
}

glm::vec3 PosedMesh::unpose(const SurfaceMesh& surface, VertexId v, const glm::vec3& p) const {
  const SkinBlend blend(surface, joints);  // per call: an operation grows the mesh between calls
  const glm::mat4 mat = blend.skinned() ? blend.matrix(v.index) : world;
  const glm::dmat4 inv = glm::inverse(glm::dmat4(mat));
  const glm::dvec4 b = inv * glm::dvec4(glm::dvec3(p), 1.0);
  if (!(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z))) return p;
  const MorphBlend morph(surface, weights);  // the vertex's own deltas, blended by MeshEditor
  return glm::vec3(glm::dvec3(b) - glm::dvec3(morph.offset(v.index)));
}

namespace {

// The world corner normals of faces `faces` of `surface` (corner normals `normals`) posed by
// `inst`, written into `out` (one per corner slot): the one kernel of every corner normal.
void corner_normals_of(const PosedMesh& inst, const SurfaceMesh& surface, const AttributeArray<glm::vec3>& normals,
                       const std::vector<std::uint32_t>& faces, std::vector<glm::vec3>& out) {
  const auto& linear = inst.linear;
  const MorphBlend morph(surface, inst.weights);
  parallel_for(faces.size(), 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::size_t f = faces[i];
      const auto& t = surface.face(FaceId(static_cast<std::uint32_t>(f)));
      for (int k = 0; k < 3; ++k) {
        const std::size_t c = 3 * f + static_cast<std::size_t>(k);
        const glm::mat3 map = linear.empty() ? glm::mat3(1.0f) : posed_normal_map(linear[t[k].index]);
        out[c] = posed_corner_normal(morph, normals, c, linear.empty() ? nullptr : &map);
      }
    }
  });
}

// The capacity a new array of `surface`'s posed corner normals is given: a corner per corner of
// the face slots operations add (operation_face_room, as the mesh and the posed positions have).
// The pages past the corners are not touched (address space only), and the array need not move:
// a step that adds faces grows it in place (follow_corner_normals), and once set aside (a
// structural step's spare) it holds a piece somewhat larger than the one it was made for, as a
// cut again at another plane after an undo makes, instead of a fresh array filled whole.
std::size_t normals_room(const SurfaceMesh& surface) { return operation_corner_room(surface.face_slots()); }

// Sizes the empty arrays of `inst` to `n` vertices with capacity `room` (the pages past `n` left
// untouched), for a posing pass that writes every element next: the pages of both are faulted
// in over the pool (from the calling thread: nested in a pool task, the pool would fault them
// serially), then the positions value-filled (a std::vector: serial, on present pages) and the
// linear maps, three quarters of the bytes, left as they are (an UninitVector).
void size_posed_arrays(PosedMesh& inst, std::size_t n, std::size_t room) {
  detail::reserve_prefaulted(inst.posed, n, room);
  detail::reserve_prefaulted(inst.linear, n, room);
  inst.posed.resize(n);
  inst.linear.resize(n);
}

// Poses every vertex of `mesh` into `inst`, whose arrays are empty, with capacity `room`, and
// measures the bounds. The positions' std::vector is sized by a serial fill run beside the
// posing chunks (detail::run_chunks_beside: usually the calling thread takes it) while the other
// threads pose chunks, the linear maps in place and the positions into a scratch array until the
// fill is done, then in place too; the chunks posed into the scratch array are copied over the
// pool after. On one thread the fill runs first and every chunk is posed in place (the scratch
// array is never touched).
void pose_into_empty(const SurfaceMesh& mesh, PosedMesh& inst, std::size_t room, const VertexPoser& pose) {
  const std::size_t n = mesh.vertex_count();
  detail::reserve_prefaulted(inst.posed, n, room);
  detail::reserve_prefaulted(inst.linear, n, room);
  inst.linear.resize(n);
  detail::UninitVector<glm::vec3> scratch(n);  // its pages fault in where a chunk writes them
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  std::vector<std::uint8_t> in_scratch(chunks, 0);
  std::atomic<bool> sized{false};
  detail::run_chunks_beside(
      chunks,
      [&](std::size_t c) {
        const std::size_t b = c * kGrain, e = std::min(n, b + kGrain);
        const bool in_place = sized.load(std::memory_order_acquire);
        glm::vec3* out = in_place ? inst.posed.data() : scratch.data();
        pose.range(b, e, out, inst.linear.data());
        in_scratch[c] = !in_place;
      },
      [&] {
        inst.posed.resize(n);
        sized.store(true, std::memory_order_release);
      });
  // bounds_of's pass (its chunks, whole posing chunks), which first copies those in `scratch`.
  static_assert(kBoundsGrain % kGrain == 0, "a bounds chunk covers whole posing chunks");
  inst.bounds = parallel_reduce(
      n, kBoundsGrain, BoundingBox(),
      [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b / kGrain; k * kGrain < e; ++k)
          if (in_scratch[k]) {
            const std::size_t kb = k * kGrain, ke = std::min(n, kb + kGrain);
            std::copy(scratch.data() + kb, scratch.data() + ke, inst.posed.data() + kb);
          }
        BoundingBox part;
        for (std::size_t i = b; i < e; ++i) part.add(inst.posed[i]);
        return part;
      },
      joined);
}

// Sizes the empty arrays of `inst`, a piece of `n` vertices, for a pass that writes every element
// next. A spare's arrays are taken when they hold the vertices and are at most twice the room the
// piece's own would have (as a piece's corner normals take a spare's, built_normals in the
// studio's scene), so a small piece does not keep a large allocation alive. New arrays get the
// piece's own room (piece_vertex_room), not its source's: a session's many small pieces would
// each keep that alive. Only the piece's elements are written; the rest of the room is address
// space unless the allocator gives back memory freed before (keep_freed_memory keeps it
// resident), and a taken spare's pages are in up to the most it held.
void size_piece_arrays(PosedMesh& inst, std::size_t n, std::vector<PosedMesh>& spare) {
  PosedMesh taken = take_smallest_fit(spare, n, 2 * operation_vertex_room(n) + 1, [](const PosedMesh& m) {
    return std::min(m.posed.capacity(), m.linear.capacity());
  });
  if (n > 0 && taken.posed.capacity() >= n && taken.linear.capacity() >= n) {  // (none taken: empty)
    // Its pages are there: only the positions past its size are filled (all are written next).
    inst.posed = std::move(taken.posed);
    inst.linear = std::move(taken.linear);
    inst.posed.resize(n);
    inst.linear.resize(n);
  } else {
    size_posed_arrays(inst, n, piece_vertex_room(n));
  }
}

// The calling thread's array of vertex normal maps, sized to `n` with its values unwritten: kept
// between calls (a pose's corner normals are computed again on every frame of a playback and
// after every step that poses a mesh afresh), so its pages are faulted in once, not on every
// call. It grows to the largest mesh posed on the thread, and moves only when it grows.
detail::UninitVector<glm::mat3>& normal_map_scratch(std::size_t n) {
  thread_local detail::UninitVector<glm::mat3> maps;
  if (maps.capacity() < n) {
    maps = detail::UninitVector<glm::mat3>();  // not resized: the old maps need no copy
    maps.reserve(n);
  }
  maps.resize(n);
  return maps;
}

}  // namespace

std::vector<glm::vec3> PosedMesh::corner_normals(const SurfaceMesh& surface) const {
  const auto* normals = surface.corner_attrs().find<glm::vec3>(attr::kNormal);
  if (!normals) return {};
  // The maps are written whole by the parallel loop (no serial zero fill first) into the calling
  // thread's scratch (normal_map_scratch); the result's pages are faulted in over the pool before
  // its fill, with room to grow (normals_room).
  detail::UninitVector<glm::mat3>& normal_maps = normal_map_scratch(linear.size());
  parallel_for(normal_maps.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) normal_maps[v] = posed_normal_map(linear[v]);
  });
  const MorphBlend morph(surface, weights);
  std::vector<glm::vec3> out;
  detail::resize_prefaulted(out, normals->size(), glm::vec3(0.0f), normals_room(surface));
  parallel_for(surface.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const auto& t = surface.face(FaceId(static_cast<std::uint32_t>(f)));
      for (int k = 0; k < 3; ++k) {
        const auto c = 3 * f + static_cast<std::size_t>(k);
        out[c] = posed_corner_normal(morph, *normals, c, normal_maps.empty() ? nullptr : &normal_maps[t[k].index]);
      }
    }
  });
  return out;
}

void PosedMesh::follow_corner_normals(const SurfaceMesh& surface, const PrimitiveChange& change,
                                      const std::vector<VertexId>& relinked, std::vector<glm::vec3>& out) const {
  const auto* normals = surface.corner_attrs().find<glm::vec3>(attr::kNormal);
  if (!normals) {
    out.clear();
    return;
  }
  const std::size_t slots = surface.face_slots();
  const std::size_t kept = std::min(change.faces_before, slots);
  std::vector<std::uint32_t> faces;  // existing faces to recompute, then the new ones
  for (FaceId f : change.faces)
    if (f.index < kept) faces.push_back(f.index);
  if (!relinked.empty() && !linear.empty()) {
    std::vector<char> moved(surface.vertex_count(), 0);
    for (VertexId v : relinked)
      if (v.index < moved.size()) moved[v.index] = 1;
    for (std::uint32_t f = 0; f < kept; ++f) {
      const auto& t = surface.face(FaceId(f));
      if (moved[t[0].index] || moved[t[1].index] || moved[t[2].index]) faces.push_back(f);
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  }
  for (std::size_t f = kept; f < slots; ++f) faces.push_back(static_cast<std::uint32_t>(f));
  out.resize(3 * slots);
  corner_normals_of(*this, surface, *normals, faces, out);
}


std::vector<glm::vec3> PosedMesh::corner_normals(const SurfaceMesh& surface, const PrimitiveOrigin& origin,
                                                 const std::vector<glm::vec3>& source_normals) const {
  std::vector<glm::vec3> out;
  corner_normals(surface, origin, source_normals, out);
  return out;
}

void PosedMesh::corner_normals(const SurfaceMesh& surface, const PrimitiveOrigin& origin,
                               const std::vector<glm::vec3>& source_normals,
                               std::vector<glm::vec3>& out) const {
  assert(&out != &source_normals);
  const auto* normals = surface.corner_attrs().find<glm::vec3>(attr::kNormal);
  const std::size_t slots = surface.face_slots();
  if (!normals || origin.faces.size() != slots) {
    out = corner_normals(surface);
    return;
  }
  assert(normals->size() == 3 * slots);  // (so the passes below write every value of `out`)
  if (out.capacity() >= normals->size()) {
    out.resize(normals->size());
  } else {  // the piece's own room (as derive_instance gives its positions)
    out = std::vector<glm::vec3>();
    detail::resize_prefaulted(out, normals->size(), glm::vec3(0.0f), piece_corner_room(slots));
  }
  // Faces with a source copy its corners (the same corner attributes, vertices with the same
  // linear maps: the kernel would give the same bits); the others are listed per chunk, joined
  // in order, and computed.
  const std::size_t chunks = (slots + kGrain - 1) / kGrain;
  std::vector<std::vector<std::uint32_t>> rims(chunks);
  glm::vec3* const to = out.data();
  parallel_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    const std::uint32_t* const from = origin.faces.data();
    const glm::vec3* const source = source_normals.data();
    const std::size_t sources = source_normals.size();
    for (std::size_t i = b; i < e; ++i)
      for (std::size_t f = i * kGrain, end = std::min(slots, (i + 1) * kGrain); f < end; ++f) {
        const std::size_t s = from[f];
        if (s == kInvalidIndex || 3 * s + 2 >= sources) {
          rims[i].push_back(static_cast<std::uint32_t>(f));
          continue;
        }
        to[3 * f] = source[3 * s];
        to[3 * f + 1] = source[3 * s + 1];
        to[3 * f + 2] = source[3 * s + 2];
      }
  });
  std::vector<std::uint32_t> faces;
  for (const auto& rim : rims) faces.insert(faces.end(), rim.begin(), rim.end());
  corner_normals_of(*this, surface, *normals, faces, out);
}

PosedMesh PosedMesh::at_positions(const SurfaceMesh& surface, std::vector<glm::vec3> posed) {
  if (!posed.empty() && posed.size() != surface.vertex_count())
    throw Error(ErrorCode::InvalidArgument, std::to_string(posed.size()) + " posed positions for " +
                                                std::to_string(surface.vertex_count()) + " vertices");
  PosedMesh inst;
  inst.posed = posed.empty() ? surface.positions() : std::move(posed);
  inst.bounds = bounds_of(inst.posed);
  inst.grid = TriangleGrid::build(surface, inst.posed);
  inst.no_unpose = true;
  return inst;
}

void PosedModel::set_pose(const Model& model, const PoseKey& key) {
  Pose pose = sample_pose(model, key);
  world_ = world_matrices(model, pose);
  weights_ = std::move(pose.weights);
  joints_.resize(model.skins.size());
  for (std::size_t s = 0; s < model.skins.size(); ++s)
    joints_[s] = joint_matrices(model, static_cast<int>(s), world_);
  key_ = key;
  valid_ = true;
}

const std::vector<float>& PosedModel::weights(int node) const {
  static const std::vector<float> kNone;
  if (node < 0 || static_cast<std::size_t>(node) >= weights_.size()) return kNone;
  return weights_[static_cast<std::size_t>(node)];
}

void PosedModel::add_piece_node(int source, int piece) {
  const auto it = key_.weights.find(source);
  if (it != key_.weights.end()) key_.weights[piece] = it->second;
}

std::size_t PosedModel::instance_count(const Model& model) {
  std::size_t count = 0;
  for (const Node& n : model.nodes)
    if (n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < model.meshes.size())
      count += model.meshes[static_cast<std::size_t>(n.mesh)].primitives.size();
  return count;
}

PosedModel PosedModel::build(const Model& model, int animation, float time, PoseDetail detail) {
  return build(model, PoseKey(animation, time), detail);
}

PosedModel PosedModel::build(const Model& model, const PoseKey& key, PoseDetail detail) {
  PosedModel index;
  index.set_pose(model, key);
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    for (std::size_t p = 0; p < model.meshes[static_cast<std::size_t>(mi)].primitives.size(); ++p)
      index.instances_[{static_cast<int>(ni), static_cast<int>(p)}] =
          index.make_instance(model, static_cast<int>(ni), static_cast<int>(p), detail);
  }
  return index;
}

void PosedModel::repose(const Model& model, int animation, float time) { repose(model, PoseKey(animation, time)); }

void PosedModel::repose(const Model& model, const PoseKey& key) {
  bool same = valid_ && world_.size() == model.nodes.size() && joints_.size() == model.skins.size() &&
              instances_.size() == instance_count(model);
  for (auto it = instances_.begin(); same && it != instances_.end(); ++it) {
    const PosedMesh& inst = it->second;
    same = instance_mesh(model, inst.node, inst.primitive) &&
           inst.mesh == model.nodes[static_cast<std::size_t>(inst.node)].mesh;
  }
  if (!same) {
    *this = build(model, key, PoseDetail::Positions);
    return;
  }
  set_pose(model, key);
  for (auto& entry : instances_) {
    PosedMesh& inst = entry.second;
    inst.joints = joints_of(model, inst.node);
    inst.world = world_.at(static_cast<std::size_t>(inst.node));
    inst.weights = weights(inst.node);
    pose_instance(*instance_mesh(model, inst.node, inst.primitive), inst, PoseDetail::Positions);
  }
}

void PosedModel::invalidate() { *this = PosedModel(); }

PosedModel PosedModel::positions_copy() const {
  PosedModel out;
  out.valid_ = valid_;
  out.key_ = key_;
  out.world_ = world_;
  out.weights_ = weights_;
  out.joints_ = joints_;
  for (const auto& [key, inst] : instances_) {
    PosedMesh& copy = out.instances_[key];
    static_cast<PosedMeshHeader&>(copy) = inst;
    copy.gridless = true;
    // As pose_into_empty sizes a new instance's: with room, the pages faulted in over the pool.
    // The linear maps (an UninitVector, sized without a fill; three quarters of the bytes) are
    // copied in chunks, the positions (a std::vector: one serial pass) beside them.
    const std::size_t room = operation_vertex_room(inst.posed.size()), maps = inst.linear.size();
    detail::reserve_prefaulted(copy.posed, inst.posed.size(), room);
    detail::reserve_prefaulted(copy.linear, maps, room);
    copy.linear.resize(maps);
    detail::parallel_for_beside(
        maps, kGrain,
        [&](std::size_t b, std::size_t e) {
          std::copy(inst.linear.begin() + b, inst.linear.begin() + e, copy.linear.begin() + b);
        },
        [&] { copy.posed.assign(inst.posed.begin(), inst.posed.end()); });
  }
  return out;
}

const std::vector<glm::mat4>& PosedModel::joints_of(const Model& model, int node) const {
  static const std::vector<glm::mat4> kNone;
  const int skin = model.nodes.at(static_cast<std::size_t>(node)).skin;
  if (skin < 0 || static_cast<std::size_t>(skin) >= joints_.size()) return kNone;
  return joints_[static_cast<std::size_t>(skin)];
}

PosedMesh PosedModel::derive_instance(const Model& model, int node, int primitive, const PosedMesh& source,
                                      const PrimitiveOrigin& origin, std::vector<PosedMesh>& spare) const {
  const SurfaceMesh& mesh = *instance_mesh(model, node, primitive);
  PosedMesh inst;
  inst.node = node;
  inst.mesh = model.nodes[static_cast<std::size_t>(node)].mesh;
  inst.primitive = primitive;
  inst.joints = joints_of(model, node);
  inst.world = world_.at(static_cast<std::size_t>(node));
  inst.weights = weights(node);
  inst.gridless = true;
  const std::size_t n = mesh.vertex_count();
  size_piece_arrays(inst, n, spare);
  // A vertex with a source has its attributes, posed alike (same world, joints and weights):
  // its position and linear map are the source's bits. The others are posed.
  const bool copy = origin.vertices.size() == n && source.linear.size() == source.posed.size();
  // The bounds are measured in the same pass (min / max are exact in any order).
  const VertexPoser pose(mesh, inst);
  inst.bounds = parallel_reduce(
      n, kGrain, BoundingBox(),
      [&](std::size_t b, std::size_t e) {
        BoundingBox part;
        for (std::size_t v = b; v < e; ++v) {
          const std::uint32_t s = copy ? origin.vertices[v] : kInvalidIndex;
          if (s < source.posed.size()) {
            inst.posed[v] = source.posed[s];
            inst.linear[v] = source.linear[s];
          } else {
            pose(v, inst);
          }
          part.add(inst.posed[v]);
        }
        return part;
      },
      joined);
  return inst;
}

PosedMesh PosedModel::make_instance(const Model& model, int node, int primitive, PoseDetail detail) const {
  const SurfaceMesh& mesh = *instance_mesh(model, node, primitive);
  PosedMesh inst;
  inst.node = node;
  inst.mesh = model.nodes[static_cast<std::size_t>(node)].mesh;
  inst.primitive = primitive;
  inst.joints = joints_of(model, node);
  inst.world = world_.at(static_cast<std::size_t>(node));
  inst.weights = weights(node);
  pose_instance(mesh, inst, detail);
  return inst;
}

// An instance with no positions yet (a new one) is posed by pose_into_empty, with room to grow
// (as interactive sessions reserve the meshes), so following the first operations never
// reallocates the whole arrays; one posed before is posed again in place.
void PosedModel::pose_instance(const SurfaceMesh& mesh, PosedMesh& inst, PoseDetail detail) const {
  const VertexPoser pose(mesh, inst);
  if (inst.posed.empty() && inst.linear.empty()) {
    pose_into_empty(mesh, inst, operation_vertex_room(mesh.vertex_count()), pose);
  } else {
    inst.posed.resize(mesh.vertex_count());
    inst.linear.resize(mesh.vertex_count());
    parallel_for(mesh.vertex_count(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v < e; ++v) pose(v, inst);
    });
    inst.bounds = bounds_of(inst.posed);
  }
  inst.gridless = detail == PoseDetail::Positions;
  inst.grid = inst.gridless ? TriangleGrid() : TriangleGrid::build(mesh, inst.posed);
  if (!inst.gridless) inst.grid.reserve(operation_face_room(mesh.face_slots()), inst.posed.capacity());
}

void PosedModel::add(const Model& model, int node, int primitive) {
  if (!instance_mesh(model, node, primitive)) return;
  instances_[{node, primitive}] = make_instance(model, node, primitive);
}

void PosedModel::prepare(const Model& model, int animation, float time, PoseDetail detail) {
  prepare(model, PoseKey(animation, time, key_.weights), detail);
}

void PosedModel::prepare(const Model& model, const PoseKey& key, PoseDetail detail) {
  if (!matches(key) || world_.size() != model.nodes.size() || joints_.size() != model.skins.size()) {
    *this = build(model, key, detail);
    return;
  }
  for (auto it = instances_.begin(); it != instances_.end();) {
    const SurfaceMesh* mesh = instance_mesh(model, it->first.first, it->first.second);
    const PosedMesh& inst = it->second;
    if (!mesh) {
      it = instances_.erase(it);
      continue;
    }
    // A gridless instance can only tell a changed mesh by its vertex count.
    const bool grid_stale =
        inst.gridless ? detail == PoseDetail::Full : inst.grid.face_count() != mesh->face_count();
    if (inst.mesh != model.nodes[static_cast<std::size_t>(inst.node)].mesh ||
        inst.posed.size() != mesh->vertex_count() || grid_stale)
      it->second = make_instance(model, inst.node, inst.primitive, detail);
    ++it;
  }
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    for (std::size_t p = 0; p < model.meshes[static_cast<std::size_t>(mi)].primitives.size(); ++p)
      if (!instances_.count({static_cast<int>(ni), static_cast<int>(p)}))
        instances_[{static_cast<int>(ni), static_cast<int>(p)}] =
            make_instance(model, static_cast<int>(ni), static_cast<int>(p), detail);
  }
}

PosedMesh* PosedModel::find(int node, int primitive) {
  auto it = instances_.find({node, primitive});
  return it == instances_.end() ? nullptr : &it->second;
}

const PosedMesh* PosedModel::find(int node, int primitive) const {
  auto it = instances_.find({node, primitive});
  return it == instances_.end() ? nullptr : &it->second;
}

void PosedModel::follow(const Model&, int node, int primitive, const SurfaceMesh& mesh, const EditLog& log) {
  if (PosedMesh* inst = find(node, primitive)) inst->follow(mesh, log);
}

void PosedMesh::follow(const SurfaceMesh& surface, const EditLog& log) {
  PosedMesh& inst = *this;
  const std::size_t old_count = inst.posed.size();
  const bool with_linear = inst.linear.size() == old_count;  // else empty: the identity
  // Vertices an edit moved, with where they were posed before it.
  std::vector<std::pair<std::uint32_t, glm::vec3>> moved;
  for (const Edit& e : log.edits)
    if (const auto* m = std::get_if<VertexMoved>(&e))
      if (m->v.index < old_count) moved.emplace_back(m->v.index, inst.posed[m->v.index]);
  std::sort(moved.begin(), moved.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  moved.erase(std::unique(moved.begin(), moved.end(), [](const auto& x, const auto& y) { return x.first == y.first; }),
              moved.end());
  // New vertices (edge and face points, tear copies, wall vertices) and moved ones, posed from
  // their final bind position and skin weights exactly as a fresh build would.
  inst.posed.resize(surface.vertex_count());
  if (with_linear) inst.linear.resize(surface.vertex_count());
  const VertexPoser pose(surface, inst);
  for (std::size_t v = old_count; v < surface.vertex_count(); ++v) {
    pose(v, inst, with_linear);
    inst.bounds.add(inst.posed[v]);
  }
  bool remeasure = false;
  for (const auto& [v, before] : moved) {
    pose(v, inst, with_linear);
    // A vertex leaving the bounds' edge may shrink them: measure again (rare: lips move inward).
    if (on_boundary(inst.bounds, before)) remeasure = true;
    inst.bounds.add(inst.posed[v]);
  }
  if (remeasure) inst.bounds = bounds_of(inst.posed);
  // The grid files the faces around moved vertices again itself (TriangleGrid::apply); a
  // gridless mesh stays gridless (`prepare` builds its grid when an operation needs one).
  if (!inst.gridless) inst.grid.apply(log, inst.posed);
}

void PosedModel::erase_primitive(int node, int primitive) {
  instances_.erase({node, primitive});
  std::vector<PosedMesh> later;
  for (auto it = instances_.lower_bound({node, primitive + 1});
       it != instances_.end() && it->first.first == node;) {
    later.push_back(std::move(it->second));
    it = instances_.erase(it);
  }
  for (PosedMesh& inst : later) {
    --inst.primitive;
    const std::pair<int, int> key{inst.node, inst.primitive};
    instances_.emplace(key, std::move(inst));
  }
}

void PosedModel::erase_node(int node) {
  instances_.erase(instances_.lower_bound({node, 0}), instances_.lower_bound({node + 1, 0}));
}

void PosedModel::rename_mesh(int node, int mesh) {
  for (auto it = instances_.lower_bound({node, 0}); it != instances_.end() && it->first.first == node; ++it)
    it->second.mesh = mesh;
}

}  // namespace deepcut
