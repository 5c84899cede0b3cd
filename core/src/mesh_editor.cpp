// SPDX-License-Identifier: MIT
#include "deepcut/core/mesh_editor.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <typeindex>
#include <vector>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace deepcut {
namespace {

// The first half of normalize_influences over kSlots slots (a constant, so the loops unroll for
// the editor's 4 and 8), or over `runtime_slots` when kSlots is 0: negative or non-finite
// weights become 0, duplicate joints are merged into their first slot.
template <int kSlots>
void clean_slots(const std::uint16_t* joints, float* weights, int runtime_slots) {
  const int slots = kSlots != 0 ? kSlots : runtime_slots;
  for (int i = 0; i < slots; ++i) {
    if (!std::isfinite(weights[i]) || weights[i] < 0.0f) weights[i] = 0.0f;
    for (int j = 0; j < i; ++j)
      if (weights[j] > 0.0f && joints[j] == joints[i]) {
        weights[j] += weights[i];
        weights[i] = 0.0f;
      }
  }
}

// The second half: the weights renormalised (the slots keep their order), zero-weight slots
// given joint 0.
template <int kSlots>
bool renormalize_slots(std::uint16_t* joints, float* weights, int runtime_slots) {
  const int slots = kSlots != 0 ? kSlots : runtime_slots;
  double sum = 0.0;
  for (int i = 0; i < slots; ++i) sum += weights[i];
  if (!(sum > 0.0)) {
    weights[0] = 1.0f;
    for (int i = 1; i < slots; ++i) {
      weights[i] = 0.0f;
      joints[i] = 0;
    }
    return false;
  }
  // Weights that already sum to 1 as closely as floats can (2e-7: a few units in the last place)
  // are kept as they are, so normalising is idempotent and an exported model re-exports to the
  // same bytes.
  const bool divide = std::abs(sum - 1.0) > 2e-7;
  for (int i = 0; i < slots; ++i) {
    if (divide) weights[i] = static_cast<float>(weights[i] / sum);
    if (weights[i] == 0.0f) joints[i] = 0;
  }
  return true;
}

template <int kSlots>
bool normalize_slots(std::uint16_t* joints, float* weights, int runtime_slots) {
  clean_slots<kSlots>(joints, weights, runtime_slots);
  return renormalize_slots<kSlots>(joints, weights, runtime_slots);
}

}  // namespace

bool normalize_influences(std::uint16_t* joints, float* weights, int slots) {
  if (slots == 4) return normalize_slots<4>(joints, weights, slots);
  if (slots == kMaxInfluences) return normalize_slots<kMaxInfluences>(joints, weights, slots);
  return normalize_slots<0>(joints, weights, slots);
}

bool renormalize_influences(std::uint16_t* joints, float* weights, int slots) {
  if (slots == 4) return renormalize_slots<4>(joints, weights, slots);
  if (slots == kMaxInfluences) return renormalize_slots<kMaxInfluences>(joints, weights, slots);
  return renormalize_slots<0>(joints, weights, slots);
}

MeshEditor::MeshEditor(SurfaceMesh& mesh) : mesh_(mesh) {
  auto& va = mesh_.vertex_attrs();
  const char* names[2][2] = {{attr::kJoints0, attr::kWeights0}, {attr::kJoints1, attr::kWeights1}};
  for (auto& pair : names) {
    auto* j = va.find<glm::u16vec4>(pair[0]);
    auto* w = va.find<glm::vec4>(pair[1]);
    if (!j || !w) break;
    joints_[skin_sets_] = j;
    weights_[skin_sets_] = w;
    ++skin_sets_;
  }
  normals_ = mesh_.corner_attrs().find<glm::vec3>(attr::kNormal);
  tangents_ = mesh_.corner_attrs().find<glm::vec4>(attr::kTangent);
}

EditLog MeshEditor::take_log() {
  EditLog out;
  out.edits.swap(log_.edits);
  return out;
}

namespace {

// blend_influences over kSlots slots (4 or 8), its arguments checked.
template <int kSlots, int kCount = 0>
void blend_slots(const std::uint16_t* joints, const float* weights, const float* w, int runtime_count,
                 std::uint16_t* out_joints, float* out_weights) {
  constexpr int slots = kSlots;
  // kCount sources (a constant, so the loop over them unrolls), or `runtime_count` when 0.
  const int count = kCount != 0 ? kCount : runtime_count;
  // Merged by joint, in the order joints first appear (sources in order, slots in order).
  struct Influence {
    std::uint16_t joint;
    float weight;
  };
  Influence acc[kMaxBlendSources * kMaxInfluences];
  int n = 0;
  for (int s = 0; s < count; ++s) {
    if (!(w[s] > 0.0f)) continue;
    for (int c = 0; c < slots; ++c) {
      const std::uint16_t joint = joints[s * slots + c];
      const float weight = weights[s * slots + c];
      if (!(weight > 0.0f)) continue;
      acc[n] = {joint, 0.0f};  // the search's sentinel: found there when the joint is new
      int found = 0;
      while (acc[found].joint != joint) ++found;
      n += found == n;
      acc[found].weight += weight * w[s];
    }
  }
  // Largest first; a stable sort keeps ties in order of first appearance (an insertion sort:
  // a few entries, and std::stable_sort would allocate a buffer for them).
  for (int i = 1; i < n; ++i) {
    const Influence x = acc[i];
    int j = i;
    for (; j > 0 && acc[j - 1].weight < x.weight; --j) acc[j] = acc[j - 1];
    acc[j] = x;
  }
  for (int i = 0; i < slots; ++i) {
    out_joints[i] = i < n ? acc[i].joint : 0;
    out_weights[i] = i < n ? acc[i].weight : 0.0f;
  }
  if (n == 0) out_joints[0] = joints[0];  // no weight anywhere: follow the first source's first joint
  // The weights are sums of positive products (no -0) under distinct joints, the unused slots 0:
  // cleaning them changes nothing unless a sum overflowed.
  bool finite = true;
  for (int i = 0; i < slots; ++i) finite &= out_weights[i] <= std::numeric_limits<float>::max();
  if (!finite) clean_slots<kSlots>(out_joints, out_weights, kSlots);
  renormalize_slots<kSlots>(out_joints, out_weights, kSlots);
}

// The skin of `n` new vertices (add_blended) with kSets JOINTS_n / WEIGHTS_n sets, from
// v: vertex v + i from the `count` sources src[count * i + s] with weights w[count * i + s]
// (kCount sources when it is not 0), in order (a source may be a vertex fixed just before).
// The sets' arrays are looked up once for the whole run.
template <int kSets, int kCount = 0>
void fix_skin(AttributeArray<glm::u16vec4>* const* joint_sets, AttributeArray<glm::vec4>* const* weight_sets,
              std::uint32_t v, const std::uint32_t* src, const float* w, int runtime_count, std::size_t n) {
  constexpr int slots = 4 * kSets;
  const int count = kCount != 0 ? kCount : runtime_count;
  glm::u16vec4* joint_data[kSets];
  glm::vec4* weight_data[kSets];
  for (int k = 0; k < kSets; ++k) {
    joint_data[k] = joint_sets[k]->data().data();
    weight_data[k] = weight_sets[k]->data().data();
  }
  for (std::size_t i = 0; i < n; ++i, src += count, w += count) {
    std::uint16_t joints[kMaxBlendSources * slots];
    float weights[kMaxBlendSources * slots];
    for (int s = 0; s < count; ++s)
      for (int k = 0; k < kSets; ++k) {
        const glm::u16vec4 j = joint_data[k][src[s]];
        const glm::vec4 x = weight_data[k][src[s]];
        for (int c = 0; c < 4; ++c) {
          joints[s * slots + 4 * k + c] = j[c];
          weights[s * slots + 4 * k + c] = x[c];
        }
      }
    std::uint16_t out_joints[slots];
    float out_weights[slots];
    blend_slots<slots, kCount>(joints, weights, w, count, out_joints, out_weights);
    const std::size_t at = v + i;
    for (int k = 0; k < kSets; ++k) {
      joint_data[k][at] = glm::u16vec4(out_joints[4 * k], out_joints[4 * k + 1], out_joints[4 * k + 2],
                                       out_joints[4 * k + 3]);
      weight_data[k][at] = glm::vec4(out_weights[4 * k], out_weights[4 * k + 1], out_weights[4 * k + 2],
                                     out_weights[4 * k + 3]);
    }
  }
}

// fix_skin over a run, dispatched once: the sets, and two sources (an edge split) as a constant.
void fix_skin_run(int sets, AttributeArray<glm::u16vec4>* const* joint_sets,
                  AttributeArray<glm::vec4>* const* weight_sets, std::uint32_t v, const std::uint32_t* src,
                  const float* w, int count, std::size_t n) {
  if (sets == 1) {
    if (count == 2)
      fix_skin<1, 2>(joint_sets, weight_sets, v, src, w, count, n);
    else
      fix_skin<1>(joint_sets, weight_sets, v, src, w, count, n);
  } else if (sets == 2) {
    if (count == 2)
      fix_skin<2, 2>(joint_sets, weight_sets, v, src, w, count, n);
    else
      fix_skin<2>(joint_sets, weight_sets, v, src, w, count, n);
  }
}

// Throws, naming `op`, unless every source of new vertex i (`sources` of them, at sources * i)
// is a vertex before it: below nv + i, where nv counts the vertices before the first new one.
void check_blend_sources(const char* op, const std::uint32_t* src, int sources, std::size_t count,
                         std::size_t nv) {
  for (std::size_t i = 0; i < count; ++i)
    for (int k = 0; k < sources; ++k)
      if (src[sources * i + k] >= nv + i)
        throw Error(ErrorCode::InvalidArgument,
                    std::string(op) + ": source " + std::to_string(src[sources * i + k]) +
                        " is not a vertex yet (" + std::to_string(nv + i) + " vertices)");
}

#if defined(__SSE__) && (defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12))
#define DEEPCUT_FOUR_FLOATS 1
// Four floats as one value (SSE; GCC >= 12 / Clang vector extensions): operators act lane by lane.
using Four = float __attribute__((vector_size(16)));
Four sqrt4(Four x) { return _mm_sqrt_ps(x); }
#endif

// Normals [begin, end) divided by their length where it is above 0 (glm::length: the square
// root of (x * x + y * y) + z * z). Four corners a step while four remain, each lane doing
// exactly those operations.
void unit_normals(glm::vec3* n, std::size_t begin, std::size_t end) {
  std::size_t c = begin;
#ifdef DEEPCUT_FOUR_FLOATS
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "normals are packed x, y, z rows");
  for (; c + 4 <= end; c += 4) {
    float* at = reinterpret_cast<float*>(n + c);
    Four p0, p1, p2;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
    std::memcpy(&p0, at, sizeof p0);
    std::memcpy(&p1, at + 4, sizeof p1);
    std::memcpy(&p2, at + 8, sizeof p2);
    const Four s0 = p0 * p0, s1 = p1 * p1, s2 = p2 * p2;
    const Four xy = __builtin_shufflevector(s1, s2, 2, 3, 5, 6);  // x2 y2 x3 y3
    const Four yz = __builtin_shufflevector(s0, s1, 1, 2, 4, 5);  // y0 z0 y1 z1
    const Four xx = __builtin_shufflevector(s0, xy, 0, 3, 4, 6);
    const Four yy = __builtin_shufflevector(yz, xy, 0, 2, 5, 7);
    const Four zz = __builtin_shufflevector(yz, s2, 1, 3, 4, 7);
    const Four len = sqrt4((xx + yy) + zz);
    // Each corner's length under its own x, y and z.
    const Four l0 = __builtin_shufflevector(len, len, 0, 0, 0, 1), l1 = __builtin_shufflevector(len, len, 1, 1, 2, 2),
               l2 = __builtin_shufflevector(len, len, 2, 3, 3, 3);
    p0 = l0 > Four{} ? p0 / l0 : p0;
    p1 = l1 > Four{} ? p1 / l1 : p1;
    p2 = l2 > Four{} ? p2 / l2 : p2;
    std::memcpy(at, &p0, sizeof p0);
    std::memcpy(at + 4, &p1, sizeof p1);
    std::memcpy(at + 8, &p2, sizeof p2);
  }
#endif
  for (; c < end; ++c) {
    const float len = glm::length(n[c]);
    if (len > 0.0f) n[c] /= len;
  }
}

// Tangents [begin, end): xyz divided by its length where that is above 0 (as unit_normals), w
// set to -1 or +1 by the sign of the w of corner source(c). Four corners a step while four
// remain; every source's w is read before any of the four is written (a corner's own w gives
// the same sign before and after: -1 stays negative, +1 positive).
template <class Source>
void unit_tangents(glm::vec4* t, std::size_t begin, std::size_t end, const Source& source) {
  std::size_t c = begin;
#ifdef DEEPCUT_FOUR_FLOATS
  static_assert(sizeof(glm::vec4) == sizeof(Four), "a tangent is four packed floats");
  for (; c + 4 <= end; c += 4) {
    const float h0 = t[source(c)].w, h1 = t[source(c + 1)].w, h2 = t[source(c + 2)].w, h3 = t[source(c + 3)].w;
    Four p0, p1, p2, p3;
    std::memcpy(&p0, t + c, sizeof p0);
    std::memcpy(&p1, t + c + 1, sizeof p1);
    std::memcpy(&p2, t + c + 2, sizeof p2);
    std::memcpy(&p3, t + c + 3, sizeof p3);
    const Four s0 = p0 * p0, s1 = p1 * p1, s2 = p2 * p2, s3 = p3 * p3;
    const Four a = __builtin_shufflevector(s0, s1, 0, 4, 1, 5);  // x0 x1 y0 y1
    const Four b = __builtin_shufflevector(s2, s3, 0, 4, 1, 5);  // x2 x3 y2 y3
    const Four zz = __builtin_shufflevector(__builtin_shufflevector(s0, s1, 2, 6, 2, 6),
                                            __builtin_shufflevector(s2, s3, 2, 6, 2, 6), 0, 1, 4, 5);
    const Four len = sqrt4((__builtin_shufflevector(a, b, 0, 1, 4, 5) + __builtin_shufflevector(a, b, 2, 3, 6, 7)) + zz);
    auto unit = [](Four p, Four l, float handedness) {  // l: the corner's length in every lane
      p = l > Four{} ? p / l : p;
      p[3] = handedness < 0.0f ? -1.0f : 1.0f;
      return p;
    };
    p0 = unit(p0, __builtin_shufflevector(len, len, 0, 0, 0, 0), h0);
    p1 = unit(p1, __builtin_shufflevector(len, len, 1, 1, 1, 1), h1);
    p2 = unit(p2, __builtin_shufflevector(len, len, 2, 2, 2, 2), h2);
    p3 = unit(p3, __builtin_shufflevector(len, len, 3, 3, 3, 3), h3);
    std::memcpy(t + c, &p0, sizeof p0);
    std::memcpy(t + c + 1, &p1, sizeof p1);
    std::memcpy(t + c + 2, &p2, sizeof p2);
    std::memcpy(t + c + 3, &p3, sizeof p3);
  }
#endif
  for (; c < end; ++c) {
    glm::vec3 xyz(t[c]);
    const float len = glm::length(xyz);
    if (len > 0.0f) xyz /= len;
    const float handedness = t[source(c)].w;
    t[c] = glm::vec4(xyz, handedness < 0.0f ? -1.0f : 1.0f);
  }
}

// Room in `log` for `more` edits, grown as a vector grows itself (at least doubling), so a
// batch's appends check no capacity and runs of batches still reallocate only now and then.
void grow_log(EditLog& log, std::size_t more) {
  const std::size_t need = log.edits.size() + more;
  if (need > log.edits.capacity()) log.edits.reserve(std::max(need, 2 * log.edits.size()));
}

}  // namespace

void blend_influences(const std::uint16_t* joints, const float* weights, const float* w, int count, int slots,
                      std::uint16_t* out_joints, float* out_weights) {
  if (count < 1 || count > kMaxBlendSources || (slots != 4 && slots != kMaxInfluences))
    throw Error(ErrorCode::InvalidArgument, "blend_influences: " + std::to_string(count) + " sources of " +
                                                std::to_string(slots) + " slots (1 to 3 sources of 4 or 8)");
  if (slots == 4)
    blend_slots<4>(joints, weights, w, count, out_joints, out_weights);
  else
    blend_slots<kMaxInfluences>(joints, weights, w, count, out_joints, out_weights);
}

// `parents` (and `w`) null: each face made from itself, each corner its own alone (remake_moved).
void MeshEditor::fix_corner_directions(FaceId first, std::size_t count, const std::uint32_t* parents,
                                       const float* w) {
  const std::size_t begin = SurfaceMesh::corner(first, 0), end = begin + 3 * count;
  if (normals_) unit_normals(normals_->data().data(), begin, end);
  if (!tangents_) return;
  // Handedness of the dominant source corner, never a blend of +1 and -1; without parents, each
  // corner's own.
  auto source = [&](std::size_t c) -> std::size_t {
    if (!parents) return c;
    const float* cw = w + 3 * (c - begin);
    int best = 0;
    for (int i = 1; i < 3; ++i)
      if (cw[i] > cw[best]) best = i;
    return SurfaceMesh::corner(FaceId(parents[(c - begin) / 3]), best);
  };
  unit_tangents(tangents_->data().data(), begin, end, source);
}

template <int kSources>
VertexId MeshEditor::add_blended(const std::uint32_t* src, const float* w, std::size_t count) {
  // The log entry's slots and the skin blend's room (fix_skin's arrays on the stack).
  static_assert(kSources >= 1 && kSources <= kMaxBlendSources,
                "a new vertex blends 1 to kMaxBlendSources vertices");
  static_assert(std::tuple_size<decltype(VertexAdded::from)>::value == kMaxBlendSources &&
                    std::tuple_size<decltype(VertexAdded::weight)>::value == kMaxBlendSources,
                "a VertexAdded entry holds kMaxBlendSources sources");
  constexpr int sources = kSources;
  const std::size_t nv = mesh_.vertex_count();
#ifndef NDEBUG
  for (std::size_t i = 0; i < count; ++i)
    for (int k = 0; k < sources; ++k) assert(src[sources * i + k] < nv + i);  // checked by the caller
#endif
  mesh_.vertex_attrs().push_blend_batch(src, w, sources, count);
  const VertexId first(static_cast<std::uint32_t>(nv));
  // The skin of the whole run (in order: a source may be a vertex of the run), one dispatch.
  if (skin_sets_ != 0) fix_skin_run(skin_sets_, joints_, weights_, first.index, src, w, sources, count);
  grow_log(log_, count);
  for (std::size_t i = 0; i < count; ++i) {
    const VertexId v(first.index + static_cast<std::uint32_t>(i));
    VertexAdded added{v, {VertexId(), VertexId(), VertexId()}, {0.0f, 0.0f, 0.0f}};
    for (int k = 0; k < sources; ++k) {
      added.from[k] = VertexId(src[sources * i + k]);
      added.weight[k] = w[sources * i + k];
    }
    log_.edits.emplace_back(added);
  }
  return first;
}

VertexId MeshEditor::add_vertex_on_edge(VertexId a, VertexId b, float t) {
  const std::uint32_t ends[2] = {a.index, b.index};
  return add_vertices_on_edges(ends, &t, 1);
}

VertexId MeshEditor::add_vertices_on_edges(const std::uint32_t* ends, const float* t, std::size_t count) {
  const std::size_t nv = mesh_.vertex_count();
  // Every end checked before the first change: a bad end late in the batch changes nothing.
  check_blend_sources("add_vertices_on_edges", ends, 2, count, nv);
  // The weights (1 - t, t) of the whole batch (on the stack for a few), so each attribute array
  // blends it in one call (side by side for a large batch: AttributeSet::push_blend_batch). A
  // vertex's skin is made again from its sources' (fix_skin, in order) whatever the array blend
  // left, so the batch's own vertices as sources give the same skin as runs made one by one.
  if (count == 0) return VertexId(static_cast<std::uint32_t>(nv));
  constexpr std::size_t kStack = 512;
  float stack[2 * kStack];
  const std::unique_ptr<float[]> heap(count > kStack ? new float[2 * count] : nullptr);  // not zeroed first
  float* w = count > kStack ? heap.get() : stack;
  for (std::size_t i = 0; i < count; ++i) {
    w[2 * i] = 1.0f - t[i];
    w[2 * i + 1] = t[i];
  }
  add_blended<2>(ends, w, count);
  return VertexId(static_cast<std::uint32_t>(nv));
}

VertexId MeshEditor::add_vertex_in_triangle(const Triangle& tri, const glm::vec3& bary) {
  const std::uint32_t src[3] = {tri[0].index, tri[1].index, tri[2].index};
  const float w[3] = {bary.x, bary.y, bary.z};
  check_blend_sources("add_vertex_in_triangle", src, 3, 1, mesh_.vertex_count());
  return add_blended<3>(src, w, 1);
}

VertexId MeshEditor::split_vertex(VertexId v) { return split_vertices(&v.index, 1); }

VertexId MeshEditor::split_vertices(const std::uint32_t* vertices, std::size_t count) {
  const std::size_t nv = mesh_.vertex_count();
  for (std::size_t i = 0; i < count; ++i)
    if (vertices[i] >= nv)
      throw Error(ErrorCode::InvalidArgument, "split_vertex: vertex " + std::to_string(vertices[i]) + " of " +
                                                  std::to_string(nv) + " vertices");
  // Each copy is the blend of its original alone (weight 1), in runs of up to kRun.
  constexpr std::size_t kRun = 64;
  float ones[kRun];
  std::fill(ones, ones + kRun, 1.0f);
  for (std::size_t i = 0; i < count; i += kRun)
    mesh_.vertex_attrs().push_blend_batch(vertices + i, ones, 1, std::min(kRun, count - i));
  const VertexId first(static_cast<std::uint32_t>(nv));
  for (std::size_t i = 0; i < count; ++i)
    log_.edits.push_back(VertexSplit{VertexId(vertices[i]), VertexId(first.index + static_cast<std::uint32_t>(i))});
  return first;
}

void MeshEditor::move_vertex(VertexId v, const glm::vec3& p) {
  mesh_.writing_vertex(v);
  auto& pos = mesh_.positions()[v.index];
  log_.edits.push_back(VertexMoved{v, pos, p});
  pos = p;
}

FaceId MeshEditor::add_face_from(const Triangle& vertices, FaceId parent,
                                 const std::array<glm::vec3, 3>& corner_bary) {
  const float w[9] = {corner_bary[0].x, corner_bary[0].y, corner_bary[0].z, corner_bary[1].x, corner_bary[1].y,
                      corner_bary[1].z, corner_bary[2].x, corner_bary[2].y, corner_bary[2].z};
  // Every face and corner attribute appended once, already blended (no default fill first).
  const FaceId f = mesh_.add_face_from(vertices[0], vertices[1], vertices[2], parent, w);
  fix_corner_directions(f, 1, &parent.index, w);
  log_.edits.push_back(FaceAdded{f, parent, vertices});
  return f;
}

FaceId MeshEditor::add_face(const Triangle& vertices) { return add_faces(&vertices, 1); }

FaceId MeshEditor::add_faces(const Triangle* faces, std::size_t count) {
  const FaceId first = mesh_.add_faces(faces, count);
  for (std::size_t i = 0; i < count; ++i)
    log_.edits.push_back(FaceAdded{FaceId(first.index + static_cast<std::uint32_t>(i)), FaceId(), faces[i]});
  return first;
}

namespace {
[[noreturn]] void throw_not_live(FaceId f) {
  throw Error(ErrorCode::InvalidArgument, "remove_face: face " + std::to_string(f.index) + " is not a live face");
}

[[noreturn]] void throw_queued_twice(FaceId f) {
  throw Error(ErrorCode::InvalidArgument,
              "apply: face " + std::to_string(f.index) + " is queued for removal twice");
}

void check_live(const SurfaceMesh& mesh, FaceId f) {
  if (f.index >= mesh.face_slots() || mesh.is_deleted(f)) throw_not_live(f);
}

// Every removal of a batch names a live face, and none twice (the second removal of a face
// would find it deleted): checked before the batch changes anything. Removals in ascending
// order (as operations queue them) need one pass; others are sorted in a copy.
void check_removals(const SurfaceMesh& mesh, const std::vector<std::pair<FaceId, std::uint32_t>>& removals) {
  bool ascending = true;
  for (std::size_t i = 0; i < removals.size(); ++i) {
    check_live(mesh, removals[i].first);
    if (i > 0 && !(removals[i - 1].first < removals[i].first)) ascending = false;
  }
  if (ascending) return;
  std::vector<FaceId> ids(removals.size());
  for (std::size_t i = 0; i < removals.size(); ++i) ids[i] = removals[i].first;
  std::sort(ids.begin(), ids.end());
  const auto twice = std::adjacent_find(ids.begin(), ids.end());
  if (twice != ids.end()) throw_queued_twice(*twice);
}
// Removes live face `f` and logs it.
void remove_live(SurfaceMesh& mesh, EditLog& log, FaceId f) {
  mesh.mark_deleted(f);
  log.edits.push_back(FaceRemoved{f, mesh.face(f)});
}
}  // namespace

void MeshEditor::remove_face(FaceId f) {
  check_live(mesh_, f);
  remove_live(mesh_, log_, f);
}

void FaceBatch::reserve(std::size_t faces, std::size_t removals) {
  faces_.reserve(faces);
  parents_.reserve(faces);
  weights_.reserve(9 * faces);
  removals_.reserve(removals);
}

namespace {

// Floats per element of `array` when it holds floats (float, glm::vec2 .. vec4); 0 for the
// integer types attributes use (a blend takes the element of largest weight: the corner itself);
// -1 for any other type.
int floats_per_element(const AttributeArrayBase& array) {
  const std::type_index t = array.type();
  if (t == typeid(float)) return 1;
  if (t == typeid(glm::vec2)) return 2;
  if (t == typeid(glm::vec3)) return 3;
  if (t == typeid(glm::vec4)) return 4;
  for (const std::type_index i :
       {std::type_index(typeid(std::uint8_t)), std::type_index(typeid(std::uint16_t)),
        std::type_index(typeid(std::uint32_t)), std::type_index(typeid(std::int32_t)),
        std::type_index(typeid(glm::u8vec4)), std::type_index(typeid(glm::u16vec4)),
        std::type_index(typeid(glm::uvec2)), std::type_index(typeid(glm::uvec4))})
    if (t == i) return 0;
  return -1;
}

// Calls fn(begin, end) for each run of consecutive places in `places` (ascending, distinct).
template <class Fn>
void for_each_run(const std::vector<std::uint32_t>& places, Fn&& fn) {
  // One run exactly when its ends are as far apart as its size says (the common case: not read
  // place by place).
  if (!places.empty() && places.back() - places.front() == places.size() - 1)
    return fn(places.front(), places.back() + 1);
  for (std::size_t i = 0; i < places.size();) {
    std::size_t j = i + 1;
    while (j < places.size() && places[j] == places[j - 1] + 1) ++j;
    fn(places[i], places[j - 1] + 1);
    i = j;
  }
}

// True when one of the `n` floats at `x` is infinite, NaN or -0, by its bits (the exponent all
// ones, or the sign bit alone): with no branch per float, four a step while four remain.
bool any_odd_float(const float* x, std::size_t n) {
  std::size_t k = 0;
  std::uint32_t bad = 0;
#ifdef DEEPCUT_FOUR_FLOATS
  using Bits = std::uint32_t __attribute__((vector_size(16)));
  const Bits exponent = {0x7f800000u, 0x7f800000u, 0x7f800000u, 0x7f800000u};
  const Bits negative_zero = {0x80000000u, 0x80000000u, 0x80000000u, 0x80000000u};
  Bits any = {0, 0, 0, 0};
  for (; k + 4 <= n; k += 4) {
    Bits u;
    std::memcpy(&u, x + k, sizeof u);
    any |= reinterpret_cast<Bits>((u & exponent) == exponent) | reinterpret_cast<Bits>(u == negative_zero);
  }
  bad = any[0] | any[1] | any[2] | any[3];
#endif
  for (; k < n; ++k) {
    std::uint32_t u;
    std::memcpy(&u, x + k, sizeof u);
    bad |= static_cast<std::uint32_t>((u & 0x7f800000u) == 0x7f800000u) | static_cast<std::uint32_t>(u == 0x80000000u);
  }
  return bad != 0;
}

// True when making each face first + moved[i] again from itself (corner k from its corners
// with weights e_k) leaves `set` as it is. A float x becomes ((0 + x * 1) + y * 0) + z * 0 (y, z
// the face's other corners): x itself when all three are finite and x is not -0 (that gives
// +0). Checked on the bits of whole runs of faces, with no branch per float.
bool remade_in_place(const AttributeSet& set, FaceId first, const std::vector<std::uint32_t>& moved) {
  for (const std::string& name : set.names()) {
    const AttributeArrayBase& array = *set.base(name);
    const int floats = floats_per_element(array);
    if (floats < 0) return false;
    if (floats == 0) continue;
    bool bad = false;
    for_each_run(moved, [&](std::uint32_t b, std::uint32_t e) {
      const auto* x = static_cast<const float*>(array.element_data(SurfaceMesh::corner(FaceId(first.index + b), 0)));
      bad |= any_odd_float(x, std::size_t(3 * floats) * (e - b));
    });
    if (bad) return false;
  }
  return true;
}

}  // namespace

void MeshEditor::remake_moved(FaceId first, const std::vector<std::uint32_t>& moved) {
  AttributeSet& corners = mesh_.corner_attrs();
  if (!remade_in_place(corners, first, moved)) {
    // Blended again, as a move blends (corner k of its own face alone), after the end of the
    // arrays, then copied back.
    std::vector<std::uint32_t> faces(moved.size());
    std::vector<float> w(9 * moved.size(), 0.0f);
    for (std::size_t i = 0; i < moved.size(); ++i) {
      faces[i] = first.index + moved[i];
      for (int k = 0; k < 3; ++k) w[9 * i + 4 * k] = 1.0f;
    }
    const std::size_t end = corners.size();
    corners.push_blend3_batch(faces.data(), w.data(), faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) corners.copy(SurfaceMesh::corner(FaceId(faces[i]), k), end + 3 * i + std::size_t(k));
    corners.resize(end);
  }
  // Each corner its own face's alone: its own handedness.
  for_each_run(moved, [&](std::uint32_t b, std::uint32_t e) {
    fix_corner_directions(FaceId(first.index + b), e - b, nullptr, nullptr);
  });
}

void MeshEditor::apply(FaceBatch& batch) {
  check_removals(mesh_, batch.removals_);
  const std::size_t n = batch.faces_.size();
  // The new faces first (their vertices checked before any change), then the log in the
  // batch's order: removing a face neither reads nor writes the faces added after it.
  const FaceId first = mesh_.add_faces_from(batch.faces_.data(), batch.parents_.data(), batch.weights_.data(), n);
  fix_corner_directions(first, n, batch.parents_.data(), batch.weights_.data());
  if (!batch.moved_.empty()) remake_moved(first, batch.moved_);
  grow_log(log_, n + batch.removals_.size());
  std::size_t r = 0;
  auto removals_before = [&](std::size_t i) {
    for (; r < batch.removals_.size() && batch.removals_[r].second <= i; ++r)
      remove_live(mesh_, log_, batch.removals_[r].first);  // checked above
  };
  for (std::size_t i = 0; i < n; ++i) {
    removals_before(i);
    const FaceId f(first.index + static_cast<std::uint32_t>(i));
    log_.edits.push_back(FaceAdded{f, FaceId(batch.parents_[i]), batch.faces_[i]});
  }
  removals_before(n);
  batch.faces_.clear();
  batch.parents_.clear();
  batch.weights_.clear();
  batch.removals_.clear();
  batch.moved_.clear();
}

}  // namespace deepcut
