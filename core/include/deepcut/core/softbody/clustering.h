// SPDX-License-Identifier: MIT
#pragma once
/// @file softbody/clustering.h
/// Soft-body particles (the paper's "Soft Body Meshes"): every
/// particle holds the vertices lying within radius rho of its seed (Euclidean distance in the
/// rest pose), a vertex may belong to several particles, and each vertex carries one influence
/// weight per particle (smooth falloff, normalised to sum 1).
///
/// `Clusters` is a cache over one `SurfaceMesh`, like `Adjacency`: `build` clusters from scratch,
/// `apply` follows an operation's `EditLog` without re-clustering. Invariants (checked by
/// `check_clusters`):
///  - coverage: every vertex referenced by a live face belongs to at least one particle, and
///    unreferenced vertices belong to none;
///  - radius: every member lies within rho of its particle's seed;
///  - connectivity: the members of a particle are connected through mesh edges whose two ends
///    are both members, so no particle holds vertices of two pieces of a cut or a tear;
///  - weights: each vertex's influences are positive and sum to 1;
///  - each particle's rest centre is the mean rest position of its members.

#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/edit_log.h"
#include "deepcut/core/surface_mesh.h"
#include "deepcut/core/uninit_vector.h"

namespace deepcut {

struct ClusterOptions {
  /// rho: the particle radius in the units of the rest positions (no default: must be > 0).
  float radius = 0.0f;
  /// Seeds are placed until every vertex lies within cover_fraction * rho of a seed (in (0, 1],
  /// default 0.7). Below 1 the particles overlap: every vertex's nearest particle then has a raw
  /// weight of at least (1 - cover_fraction^2)^2 (0.26 by default) while weights fade to ~0 at
  /// a particle's rim, so the normalised weights, and with them the vertex displacements, vary
  /// continuously across particle borders. At 1 the cover is as sparse as the radius allows
  /// (fewest particles), with weight jumps where a vertex sits near the rim of its only particle.
  float cover_fraction = 0.7f;
};

/// One vertex's membership in one particle.
struct Influence {
  std::uint32_t particle = kInvalidIndex;
  float weight = 0.0f;  ///< normalised: a vertex's weights sum to 1
};

/// A vertex's influences, contiguous in memory.
struct InfluenceRange {
  const Influence* first = nullptr;
  const Influence* last = nullptr;
  const Influence* begin() const { return first; }
  const Influence* end() const { return last; }
  std::size_t size() const { return static_cast<std::size_t>(last - first); }
  bool empty() const { return first == last; }
};

/// What `Clusters::apply` changed, so a simulation can follow (see `sync_soft_body`).
struct ClusterUpdate {
  /// A particle created by `apply`: a connected part split off `parent`, or (parent invalid) a
  /// particle seeded at a vertex no existing particle could take.
  struct NewParticle {
    std::uint32_t particle = kInvalidIndex;
    std::uint32_t parent = kInvalidIndex;
  };
  /// Particles whose members changed (their rest centres were recomputed), new ones included.
  std::vector<std::uint32_t> touched;
  std::vector<NewParticle> created;
  std::size_t vertices_added = 0;    ///< vertices that joined the clusters
  std::size_t vertices_removed = 0;  ///< vertices that left (no longer referenced by a live face)
  std::size_t particles_split = 0;   ///< particles found holding two or more disconnected parts
};

/// Counts for reports (`deepcut cluster`). Empty particle slots are not counted.
struct ClusterStats {
  std::size_t particles = 0;
  std::size_t min_vertices = 0, max_vertices = 0;  ///< members per particle
  double mean_vertices = 0.0;
  std::size_t memberships = 0;         ///< sum of members over particles
  std::size_t covered_vertices = 0;    ///< referenced vertices in at least one particle
  std::size_t uncovered_vertices = 0;  ///< referenced vertices in none (0 when the invariants hold)
};

class Clusters {
 public:
  /// Clusters the vertices referenced by live faces of `mesh`.
  ///
  /// Seeds are chosen by farthest-point sampling over a uniform grid (never all pairs): the
  /// next seed is the vertex farthest from all seeds so far, until every vertex lies within
  /// cover_fraction * rho of a seed. The seed order does not depend on rho, so the number of
  /// seeds falls as rho grows. Each seed's ball (the vertices within rho) is then split into
  /// its connected parts (mesh edges between members); a part other than the largest is
  /// dropped when each of its vertices is also covered by another particle's main part (a
  /// sliver of a neighbouring surface sheet), and becomes a particle of its own otherwise.
  /// Raw weights fall off as (1 - (d / rho)^2)^2 (floored at 1e-6), then are normalised per
  /// vertex.
  /// @param mesh     triangle mesh; only vertices referenced by live faces are clustered.
  /// @param rest     one rest position per vertex (size == mesh.vertex_count()): the mesh's
  ///                 bind positions, or the world positions of the rest pose.
  /// @param options  radius rho (> 0, finite) and cover fraction (in (0, 1]).
  /// @throws Error{InvalidArgument} for a bad radius or cover fraction, or a size mismatch;
  ///         Error{InvalidInput} for a non-finite rest position of a referenced vertex.
  /// @note Typically O(V log V + memberships). With a tiny rho relative to the model the grid is coarser
  ///       than rho (its cell count is capped), which costs time but not correctness.
  static Clusters build(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest,
                        const ClusterOptions& options);
  /// Same, with the mesh's bind positions as the rest positions.
  static Clusters build(const SurfaceMesh& mesh, const ClusterOptions& options);

  /// Follows the edits of one or more operations, in order, without re-clustering:
  ///  - a vertex no longer referenced by a live face leaves its particles;
  ///  - `VertexAdded` joins its sources' particles with the sources' influences interpolated
  ///    by the edit's weights, `VertexSplit` copies the original's particles;
  ///  - memberships farther than rho from the seed are dropped (added or moved vertices); a
  ///    vertex left with none joins a particle whose seed lies within rho, or seeds a new one;
  ///  - every particle holding an edited vertex is split into its connected parts (as in
  ///    `build`), so no particle keeps vertices of both sides of a cut or tear;
  ///  - rest centres are recomputed for the touched particles only.
  /// Particle ids stay stable: a particle that loses all its members keeps its (empty) slot,
  /// and new particles are appended.
  /// @param mesh       the mesh after the edits.
  /// @param rest       its rest positions, one per vertex (same frame as `build`).
  /// @param log        the edits since the last build/apply.
  /// @param adjacency  optional: the mesh's adjacency, already updated with `log`. With it the
  ///                   connectivity check visits only the faces around edited particles;
  ///                   without it, one pass over the faces (O(F), no allocation per face).
  /// @throws Error{InvalidArgument} if `rest` or `adjacency` does not match the mesh, an edit
  ///         names a vertex or face outside the mesh, or the log does not fit the mesh (a face it
  ///         removes is still live, or is removed twice); Error{InvalidInput} for a non-finite
  ///         rest position of an edited vertex. The log is checked before anything changes, so
  ///         after a throw the clusters are as they were.
  /// @returns what changed.
  /// @note Cost: O(edits) to walk the log, plus the members of the touched particles and (with
  ///       `adjacency`) their faces; a cut across the cactus trunk costs about as much as the cut.
  /// @note A tear separates its lips only where a particle cannot reach round an end of the
  ///       slit: near the ends the lips are still joined by the surface, and a particle there
  ///       may keep both (it is connected through its members).
  ClusterUpdate apply(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest, const EditLog& log,
                      const Adjacency* adjacency = nullptr);
  /// Same, with the mesh's bind positions as the rest positions.
  ClusterUpdate apply(const SurfaceMesh& mesh, const EditLog& log, const Adjacency* adjacency = nullptr);

  float radius() const { return radius_; }
  /// Number of particle slots (ids are 0 .. slots-1); empty slots have no members.
  std::size_t particle_slots() const { return seeds_.size(); }
  /// Number of particles with at least one member.
  std::size_t particle_count() const;
  /// Number of vertices the clusters know (the mesh's vertex count at the last build/apply).
  std::size_t vertex_count() const { return rows_.size(); }

  /// Members of particle `p`, sorted by vertex index.
  const std::vector<std::uint32_t>& members(std::uint32_t p) const { return members_[p]; }
  /// The seed position of `p` (rest space): every member lies within rho of it.
  const glm::vec3& seed(std::uint32_t p) const { return seeds_[p]; }
  /// Mean rest position of the members of `p` (its seed when it has none).
  const glm::vec3& rest_centre(std::uint32_t p) const { return centres_[p]; }
  /// Influences of vertex `v`, sorted by particle (empty when it is in no particle).
  InfluenceRange influences(VertexId v) const {
    const Row& r = rows_[v.index];
    return {pool_.data() + r.begin, pool_.data() + r.begin + r.size};
  }

 private:
  /// The per-vertex arrays (rows, pool, face counts) are UnfilledVectors: a build sizes them for
  /// millions of entries and writes them over the thread pool instead of filling them first on
  /// the calling thread.

  struct Row {
    std::uint32_t begin = 0, size = 0, capacity = 0;
  };
  /// Replaces the influences of `v` (kept sorted by particle).
  void set_row(std::uint32_t v, const Influence* first, std::size_t count);
  /// Sorts the row of `v` by particle.
  void sort_row(std::uint32_t v);
  void compact_pool();
  /// Scales the weights of `v` to sum 1 (all equal when they sum to 0).
  void renormalise(std::uint32_t v);
  /// Rows and pool, then member lists, of a fresh build for the live vertices `ids` (seeds_ and
  /// radius_ set; rows_ sized).
  void build_rows(const std::vector<glm::vec3>& rest, const UnfilledVector<std::uint32_t>& ids);
  void build_member_lists(const UnfilledVector<std::uint32_t>& ids);
  /// First step of `apply`: replays `log` on the rows (rows for its new vertices, the live-face
  /// counts of its faces' corners); rows_ and face_refs_ must already be sized to the mesh.
  /// Returns the vertices to revisit, sorted and unique.
  std::vector<std::uint32_t> replay_log(const EditLog& log);
  /// Next step of `apply`: revisits the rows of `vertices` (`old_count`: the vertices known
  /// before): dead vertices leave (counted in `update.vertices_removed`), memberships beyond rho
  /// go, uncovered vertices join a particle, new (appended to `update.created`) if none is near;
  /// live vertices new to the clusters, or known without influences, are counted in
  /// `update.vertices_added`. Returns the particles that uncovered vertices joined, in order.
  std::vector<std::uint32_t> refit_rows(const std::vector<glm::vec3>& rest,
                                        const std::vector<std::uint32_t>& vertices, std::size_t old_count,
                                        ClusterUpdate& update);
  void recompute_centre(std::uint32_t p, const std::vector<glm::vec3>& rest);
  std::uint32_t new_particle(const glm::vec3& seed);
  /// Splits the listed particles into their connected parts (see `build`); appends new particles
  /// to `created` and returns how many particles were disconnected. `for_each_face(fn)` calls
  /// `fn(triangle)` for (at least) every live face around the members of those particles.
  /// Compiled (clustering_split.cpp) only for the three face walkers of the core-private
  /// softbody/clustering_detail.h.
  template <class ForEachFace>
  std::size_t split_disconnected(const std::vector<std::uint32_t>& particles, ForEachFace&& for_each_face,
                                 std::vector<ClusterUpdate::NewParticle>& created);
  /// Last step of split_disconnected (clustering_split.cpp, its only user): each part in
  /// `minors` not marked in `drop` becomes a particle of its own (appended to `created`); the
  /// rows holding a part's entries are fixed.
  template <class Minors>
  void rename_minor_parts(Minors& minors, const std::vector<std::uint8_t>& drop,
                          std::vector<ClusterUpdate::NewParticle>& created);

  float radius_ = 0.0f;
  std::vector<glm::vec3> seeds_;
  std::vector<glm::vec3> centres_;
  std::vector<std::vector<std::uint32_t>> members_;
  UnfilledVector<Row> rows_;        // one per vertex: its influences in pool_, sorted by particle
  UnfilledVector<Influence> pool_;  // rows, with gaps left by relocated rows
  std::size_t pool_garbage_ = 0;    // entries in pool_ no row uses
  UnfilledVector<std::uint32_t>
      face_refs_;  // live faces per vertex (corners, so a degenerate face counts twice)
};

/// Particle counts, members per particle and coverage.
/// @param mesh  the mesh the clusters follow (its live faces define "referenced" vertices).
ClusterStats cluster_stats(const Clusters& clusters, const SurfaceMesh& mesh);

/// Checks every invariant listed at the top of this file against `mesh` and `rest`, computing
/// connectivity from scratch (independently of how `build`/`apply` did). Tests use it after
/// every operation.
/// @returns one line per violation (at most `max_problems`), empty when all hold.
std::vector<std::string> check_clusters(const Clusters& clusters, const SurfaceMesh& mesh,
                                        const std::vector<glm::vec3>& rest, std::size_t max_problems = 20);

/// One mesh to cluster and its rest positions (both must outlive the call).
struct ClusterInput {
  const SurfaceMesh* mesh = nullptr;
  const std::vector<glm::vec3>* rest = nullptr;
};

/// The radius whose clustering (with `options.cover_fraction`; `options.radius` is ignored) has
/// the particle count closest to `target` (ties: the larger radius), found by bisection on rho
/// between 1e-4 of the model size and the model size. Several meshes (a model's primitives)
/// count together.
/// @param[out] particles  if not null, the particle count at the returned radius.
/// @throws Error{InvalidArgument} if `target` is 0, no mesh has a live face, or a rest array
///         does not match its mesh.
/// @note Runs `build` on every mesh about 25 times.
float radius_for_particle_count(const std::vector<ClusterInput>& inputs, std::size_t target,
                                const ClusterOptions& options = {}, std::size_t* particles = nullptr);
/// Same, for one mesh.
float radius_for_particle_count(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest,
                                std::size_t target, const ClusterOptions& options = {},
                                std::size_t* particles = nullptr);

}  // namespace deepcut
