// SPDX-License-Identifier: MIT
#pragma once
// The stages of a tear and the data they hand each other. Private to the tear: tear.cpp runs
// them (sweep -> slit insertion, per sweep facet -> lips), ops/tear.h describes the operation.

#include <cstddef>
#include <cstdint>
#include <memory_resource>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/posed_model.h"
#include "ops/common/crossing_table.h"
#include "ops/common/placement.h"
#include "ops/common/posed_overlay.h"
#include "ops/tear/sweep.h"

namespace deepcut::detail::tear {

// A tear's hash maps and sets take their nodes from one arena per tear (a bump allocator freed
// when the tear ends) instead of one malloc and free per node: same containers, same hashing and
// iteration order, so the same results.
template <class K, class V>
using Map = std::pmr::unordered_map<K, V>;
template <class K>
using Set = std::pmr::unordered_set<K>;

inline VertexId key_lo(std::uint64_t key) { return VertexId(static_cast<std::uint32_t>(key >> 32)); }
inline VertexId key_hi(std::uint64_t key) { return VertexId(static_cast<std::uint32_t>(key & 0xffffffffu)); }

/// Posed positions and bind-to-world linear maps during one tear: the PosedMesh's for the
/// vertices it holds, the tear's own for the vertices it adds (where they are made, so the
/// predicates see the surface the blade was placed against), and the placement that puts each
/// new or moved vertex at its posed point (ops/common/placement.h).
class TearPose {
 public:
  TearPose(const PosedMesh& input, const SurfaceMesh& mesh, std::pmr::memory_resource* arena)
      : posed_(input.posed), input_linear_(input.linear), new_linear_(arena), placement_(input, mesh) {}

  glm::vec3 posed(std::uint32_t v) const { return posed_(v); }
  /// The linear map of `v`: the input's, or the blend made for a new vertex (identity when the
  /// input has none).
  glm::mat3 linear(VertexId v) const {
    if (input_linear_.empty()) return glm::mat3(1.0f);
    if (v.index < input_linear_.size()) return input_linear_[v.index];
    auto it = new_linear_.find(v.index);
    return it == new_linear_.end() ? glm::mat3(1.0f) : it->second;
  }
  /// Records new vertex `v`, just made by `editor` from `src` with weights `w` (n of each), at
  /// posed position `p`: its linear map blended likewise, its bind position `p` unposed.
  void add(MeshEditor& editor, VertexId v, const glm::dvec3& p, const VertexId* src, const double* w, int n) {
    posed_.set_added(v, glm::vec3(p));
    if (!input_linear_.empty()) {
      glm::mat3 m(0.0f);
      for (int i = 0; i < n; ++i) m += float(w[i]) * linear(src[i]);
      new_linear_[v.index] = m;
    }
    placement_.place(editor, v, glm::vec3(p));
  }
  /// Records `copy`, a copy of `v` (MeshEditor::split_vertex): the same posed position and map.
  void add_copy(VertexId copy, VertexId v) {
    posed_.set_added(copy, posed_(v.index));
    if (!input_linear_.empty()) new_linear_[copy.index] = linear(v);
  }
  const Placement& placement() const { return placement_; }

 private:
  PosedOverlay<glm::vec3> posed_;
  const UninitVector<glm::mat3>& input_linear_;
  Map<std::uint32_t, glm::mat3> new_linear_;
  Placement placement_;
};

/// What every stage works on: the mesh and its editor, the posed positions, the grid over the
/// input faces, the tolerance and the arena.
struct TearContext {
  SurfaceMesh& mesh;
  MeshEditor& editor;
  TearPose& pose;
  const TriangleGrid& grid;
  std::uint32_t first_new_face;  ///< faces from here on were made by this tear
  double tol;                    ///< snapping tolerance, world units
  std::pmr::memory_resource* arena;
};

/// The slits so far: what slit insertion hands to the lips.
struct Slits {
  explicit Slits(std::pmr::memory_resource* arena) : torn(arena) {}
  /// Torn edges (edge_key) -> the sweep facet that tore them.
  Map<std::uint64_t, std::size_t> torn;
  /// Faces examined or made (every face around a slit vertex is among them).
  std::vector<FaceId> region;
  /// Crossings merged into one vertex (ops/common/crossing_table.h), over every facet.
  NeedleMerges merges;
  /// Mesh edges split where the tear surface crosses them.
  std::size_t intersections = 0;

  void add_torn(VertexId a, VertexId b, std::size_t facet) {
    if (a == b) return;
    torn.emplace(edge_key(a, b), facet);
  }
  VertexId resolve(VertexId v) const { return merges.merged(v); }
};

/// Slit insertion (slit_insertion.cpp): splits the mesh along where `facet` crosses it (edges it
/// crosses, edges lying in its plane, points where it ends inside a face) and records the torn
/// edges in `slits`. Leaves the mesh as it is when the facet tears nothing.
void insert_slit(TearContext& ctx, const SweepFacet& facet, std::size_t facet_index, Slits& slits);

/// Lips (lips.cpp), first step: a slit made of one torn edge between two ends gets a vertex at
/// the edge's midpoint, so it has an interior vertex to duplicate.
void split_lone_edges(TearContext& ctx, Slits& slits);

/// What separating and opening the lips gives.
struct Separation {
  std::vector<VertexId> tear_vertices;  ///< sorted
  std::size_t slits = 0, closed_slits = 0;
  float opening = 0.0f;
};

/// Lips (lips.cpp): splits the vertices along the torn edges into one copy per wedge of faces
/// between torn edges, then pushes the lips apart by up to `width` (tapered along each slit).
Separation separate_and_open(TearContext& ctx, const std::vector<SweepFacet>& facets, float width, Slits& slits);

}  // namespace deepcut::detail::tear
