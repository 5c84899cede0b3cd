// SPDX-License-Identifier: MIT
// Soft-body clusters: statistics, the invariant checks and the radius search for a particle count.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "deepcut/core/softbody/clustering.h"
#include "softbody/clustering_detail.h"

namespace deepcut {

using namespace clustering_detail;

ClusterStats cluster_stats(const Clusters& clusters, const SurfaceMesh& mesh) {
  ClusterStats s;
  std::size_t min_v = std::numeric_limits<std::size_t>::max(), max_v = 0;
  for (std::uint32_t p = 0; p < clusters.particle_slots(); ++p) {
    const std::size_t m = clusters.members(p).size();
    if (m == 0) continue;
    ++s.particles;
    s.memberships += m;
    min_v = std::min(min_v, m);
    max_v = std::max(max_v, m);
  }
  if (s.particles) {
    s.min_vertices = min_v;
    s.max_vertices = max_v;
    s.mean_vertices = double(s.memberships) / double(s.particles);
  }
  std::vector<std::uint8_t> referenced(mesh.vertex_count(), 0);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (const VertexId v : t) referenced[v.index] = 1;
  });
  for (std::uint32_t v = 0; v < referenced.size(); ++v) {
    if (!referenced[v]) continue;
    const bool covered = v < clusters.vertex_count() && !clusters.influences(VertexId(v)).empty();
    ++(covered ? s.covered_vertices : s.uncovered_vertices);
  }
  return s;
}

namespace {

// The problems check_clusters finds, up to `max` lines.
struct Problems {
  std::vector<std::string> lines;
  std::size_t max;
  void report(const std::string& line) {
    if (lines.size() < max) lines.push_back(line);
  }
};

// Rows: coverage, weights, radius, and agreement with the member lists (`referenced`: per vertex,
// whether a live face uses it).
void check_rows(const Clusters& clusters, const std::vector<glm::vec3>& rest,
                const std::vector<std::uint8_t>& referenced, Problems& problems) {
  const float rho = clusters.radius();
  const float limit2 = rho * rho * (1.0f + kRadiusSlack) * (1.0f + kRadiusSlack);
  const std::size_t slots = clusters.particle_slots();
  for (std::uint32_t v = 0; v < referenced.size(); ++v) {
    const InfluenceRange row = clusters.influences(VertexId(v));
    if (referenced[v] && row.empty())
      problems.report("coverage: vertex " + std::to_string(v) + " is in no particle");
    if (!referenced[v] && !row.empty())
      problems.report("vertex " + std::to_string(v) + " has no live face but is in " +
                      std::to_string(row.size()) + " particles");
    double sum = 0.0;
    for (const Influence* a = row.begin(); a != row.end(); ++a) {
      if (a->particle >= slots) {
        problems.report("vertex " + std::to_string(v) + " names particle " + std::to_string(a->particle) +
                        " of " + std::to_string(slots));
        continue;
      }
      if (!(a->weight > 0.0f) || !std::isfinite(a->weight))
        problems.report("vertex " + std::to_string(v) + " has weight " + std::to_string(a->weight) +
                        " in particle " + std::to_string(a->particle));
      sum += a->weight;
      for (const Influence* b = row.begin(); b != a; ++b)
        if (b->particle == a->particle)
          problems.report("vertex " + std::to_string(v) + " lists particle " + std::to_string(a->particle) +
                          " twice");
      const auto& m = clusters.members(a->particle);
      if (!std::binary_search(m.begin(), m.end(), v))
        problems.report("vertex " + std::to_string(v) + " is influenced by particle " +
                        std::to_string(a->particle) + " but not among its members");
      const float d2 = distance2(rest[v], clusters.seed(a->particle));
      if (d2 > limit2)
        problems.report("radius: vertex " + std::to_string(v) + " lies " + std::to_string(std::sqrt(d2)) +
                        " from the seed of particle " + std::to_string(a->particle) + " (rho " +
                        std::to_string(rho) + ")");
    }
    if (!row.empty() && std::abs(sum - 1.0) > 1e-4)
      problems.report("vertex " + std::to_string(v) + " weights sum to " + std::to_string(sum));
  }
}

// How many members of particle `p` (`m`, each stamped `p` in `stamp`) a breadth-first search from
// the first one reaches over edges between members. Leaves the reached members stamped with a
// visited marker.
std::size_t connected_members(const SurfaceMesh& mesh, const Adjacency& adjacency, std::uint32_t p,
                              const std::vector<std::uint32_t>& m, std::vector<std::uint32_t>& stamp,
                              std::vector<std::uint32_t>& queue) {
  std::size_t reached = 1;
  queue.assign(1, m[0]);
  stamp[m[0]] = kInvalidIndex - 1 - p % 2;  // visited marker distinct from "member of p"
  const std::uint32_t visited = stamp[m[0]];
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const std::uint32_t v = queue[q];
    if (v >= adjacency.vertex_count()) continue;
    for (const FaceId f : adjacency.vertex_faces(VertexId(v)))
      for (const VertexId u : mesh.face(f))
        if (stamp[u.index] == p) {
          stamp[u.index] = visited;
          queue.push_back(u.index);
          ++reached;
        }
  }
  return reached;
}

// Particles: sorted members that agree with the rows, rest centres, connectivity. Stops at a
// member outside the mesh.
void check_particles(const Clusters& clusters, const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest,
                     Problems& problems) {
  const std::size_t n = mesh.vertex_count();
  const Adjacency adjacency = Adjacency::build(mesh);
  std::vector<std::uint32_t> stamp(n, kInvalidIndex), queue;
  for (std::uint32_t p = 0; p < clusters.particle_slots(); ++p) {
    const auto& m = clusters.members(p);
    if (m.empty()) continue;
    if (!std::is_sorted(m.begin(), m.end()) || std::adjacent_find(m.begin(), m.end()) != m.end())
      problems.report("particle " + std::to_string(p) + ": members not sorted and unique");
    glm::dvec3 sum(0.0);
    for (std::uint32_t v : m) {
      if (v >= n) {
        problems.report("particle " + std::to_string(p) + " lists vertex " + std::to_string(v) +
                        " outside the mesh");
        return;
      }
      bool listed = false;
      for (const Influence& in : clusters.influences(VertexId(v))) listed = listed || in.particle == p;
      if (!listed)
        problems.report("particle " + std::to_string(p) + " lists vertex " + std::to_string(v) +
                        " without an influence");
      sum += glm::dvec3(rest[v]);
      stamp[v] = p;
    }
    const glm::vec3 centre(sum / double(m.size()));
    const float tol = 1e-4f * std::max(clusters.radius(), glm::length(centre));
    if (glm::length(centre - clusters.rest_centre(p)) > tol)
      problems.report("particle " + std::to_string(p) + ": rest centre is stale");
    const std::size_t reached = connected_members(mesh, adjacency, p, m, stamp, queue);
    if (reached != m.size())
      problems.report("connectivity: particle " + std::to_string(p) + " holds " + std::to_string(m.size()) +
                      " vertices of which only " + std::to_string(reached) + " are connected to vertex " +
                      std::to_string(m[0]) + " through its members");
    for (std::uint32_t v : m) stamp[v] = kInvalidIndex;
  }
}

}  // namespace

std::vector<std::string> check_clusters(const Clusters& clusters, const SurfaceMesh& mesh,
                                        const std::vector<glm::vec3>& rest, std::size_t max_problems) {
  Problems problems{{}, max_problems};
  const std::size_t n = mesh.vertex_count();
  if (clusters.vertex_count() != n) {
    problems.report("clusters know " + std::to_string(clusters.vertex_count()) + " vertices, the mesh has " +
                    std::to_string(n));
    return problems.lines;
  }
  if (rest.size() != n) {
    problems.report("rest positions: " + std::to_string(rest.size()) + " for " + std::to_string(n) +
                    " vertices");
    return problems.lines;
  }
  std::vector<std::uint8_t> referenced(n, 0);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (const VertexId v : t) referenced[v.index] = 1;
  });
  check_rows(clusters, rest, referenced, problems);
  check_particles(clusters, mesh, rest, problems);
  return problems.lines;
}

float radius_for_particle_count(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest,
                                std::size_t target, const ClusterOptions& options, std::size_t* particles) {
  return radius_for_particle_count({ClusterInput{&mesh, &rest}}, target, options, particles);
}

float radius_for_particle_count(const std::vector<ClusterInput>& inputs, std::size_t target,
                                const ClusterOptions& options, std::size_t* particles) {
  if (target == 0)
    throw Error(ErrorCode::InvalidArgument, "cluster: the target particle count must be at least 1");
  BoundingBox box;
  std::size_t live = 0;
  for (const ClusterInput& in : inputs) {
    if (!in.mesh || !in.rest) throw Error(ErrorCode::InvalidArgument, "cluster: null mesh or rest positions");
    check_rest(*in.mesh, *in.rest, "cluster");
    in.mesh->for_each_face([&](FaceId, const Triangle& t) {
      ++live;
      for (const VertexId v : t) box.add((*in.rest)[v.index]);
    });
  }
  if (live == 0) throw Error(ErrorCode::InvalidArgument, "cluster: the mesh has no live face");
  const double size = std::max(double(box.diagonal()), 1e-12);
  double lo = size * 1e-4, hi = size;
  double best_r = hi;
  std::size_t best_n = 0;
  bool have = false;
  const auto diff = [&](std::size_t c) { return c > target ? c - target : target - c; };
  auto consider = [&](double r) {
    ClusterOptions o = options;
    o.radius = float(r);
    std::size_t count = 0;
    for (const ClusterInput& in : inputs) count += Clusters::build(*in.mesh, *in.rest, o).particle_count();
    if (!have || diff(count) < diff(best_n) || (diff(count) == diff(best_n) && r > best_r)) {
      best_r = r;
      best_n = count;
      have = true;
    }
    return count;
  };
  consider(hi);
  for (int i = 0; i < 26 && best_n != target; ++i) {
    const double mid = std::sqrt(lo * hi);
    if (consider(mid) > target)
      lo = mid;
    else
      hi = mid;
  }
  if (particles) *particles = best_n;
  return float(best_r);
}

}  // namespace deepcut
