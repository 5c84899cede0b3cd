// SPDX-License-Identifier: MIT
// Soft-body clusters: Clusters::apply, which follows an operation's edit log without
// re-clustering (the split into connected parts is clustering_split.cpp's).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "deepcut/core/errors.h"
#include "deepcut/core/softbody/clustering.h"
#include "softbody/clustering_detail.h"
#include "softbody/point_grid.h"

namespace deepcut {
namespace {

using namespace clustering_detail;

// Checks that `log` fits `mesh` before `apply` changes anything: every vertex and face it names
// exists (vertices with a finite rest position), and every face it removes is deleted in the mesh
// and was live (`face_refs`: the live faces per vertex before the log).
template <class Refs>
void check_log(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest, const EditLog& log,
               const Refs& face_refs) {
  const std::size_t n = mesh.vertex_count();
  auto check_vertex = [&](VertexId v) {
    if (v.index >= n)
      throw Error(ErrorCode::InvalidArgument, "clusters.apply: edit names vertex " + std::to_string(v.index) +
                                                  ", the mesh has " + std::to_string(n));
    const glm::vec3& p = rest[v.index];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(ErrorCode::InvalidInput,
                  "clusters.apply: vertex " + std::to_string(v.index) + " has a non-finite position");
  };
  auto check_face = [&](FaceId f, const Triangle& t) {
    if (f.index >= mesh.face_slots())
      throw Error(ErrorCode::InvalidArgument, "clusters.apply: edit names face " + std::to_string(f.index) +
                                                  ", the mesh has " + std::to_string(mesh.face_slots()));
    for (const VertexId v : t) check_vertex(v);
  };

  std::vector<std::pair<std::uint32_t, std::int64_t>> refs;  // (vertex, live faces), sorted
  auto live_faces = [&](std::uint32_t v) -> std::int64_t& {
    auto it = std::lower_bound(refs.begin(), refs.end(), std::make_pair(v, std::int64_t(-1)),
                               [](const auto& a, const auto& b) { return a.first < b.first; });
    if (it == refs.end() || it->first != v)
      it = refs.insert(it, {v, v < face_refs.size() ? std::int64_t(face_refs[v]) : 0});
    return it->second;
  };
  for (const Edit& edit : log.edits) {
    if (const auto* e = std::get_if<VertexAdded>(&edit)) {
      check_vertex(e->v);
      for (const VertexId from : e->from)
        if (from.valid()) check_vertex(from);
    } else if (const auto* sp = std::get_if<VertexSplit>(&edit)) {
      check_vertex(sp->original);
      check_vertex(sp->copy);
    } else if (const auto* m = std::get_if<VertexMoved>(&edit)) {
      check_vertex(m->v);
    } else if (const auto* fa = std::get_if<FaceAdded>(&edit)) {
      check_face(fa->f, fa->vertices);
      for (const VertexId v : fa->vertices) ++live_faces(v.index);
    } else if (const auto* fr = std::get_if<FaceRemoved>(&edit)) {
      check_face(fr->f, fr->vertices);
      // Face ids are never reused, so a face the log removes is deleted in the edited mesh.
      if (!mesh.is_deleted(fr->f))
        throw Error(ErrorCode::InvalidArgument, "clusters.apply: the log removes face " +
                                                    std::to_string(fr->f.index) +
                                                    " but the mesh still has it (log and mesh do not match)");
      for (const VertexId v : fr->vertices)
        if (--live_faces(v.index) < 0)
          throw Error(ErrorCode::InvalidArgument,
                      "clusters.apply: face " + std::to_string(fr->f.index) +
                          " is removed twice or was never added (log applied twice?)");
    }
  }
}

// The influences of a vertex added by interpolation: its sources' influences, weighted by the
// edit's weights and summed per particle (in order of first appearance), into `acc`.
void blend_influences(const VertexAdded& e, const Clusters& clusters, std::vector<Influence>& acc) {
  acc.clear();
  for (int i = 0; i < 3; ++i) {
    if (!e.from[i].valid() || !(e.weight[i] > 0.0f)) continue;
    for (const Influence& in : clusters.influences(e.from[i])) {
      auto it =
          std::find_if(acc.begin(), acc.end(), [&](const Influence& a) { return a.particle == in.particle; });
      if (it == acc.end())
        acc.push_back({in.particle, e.weight[i] * in.weight});
      else
        it->weight += e.weight[i] * in.weight;
    }
  }
}

// Where an uncovered vertex goes: the nearest live particle whose seed lies within rho of it
// (ties to the higher index). The candidates come from a grid over the seeds of the particles
// live at the first question (a scan of every particle for every vertex would make long edit
// sequences quadratic) plus the particles created since, reported with `created`: members are
// only added meanwhile, so that is the live set.
class NearestLiveParticle {
 public:
  // `seeds`: the clusters' seed array (read once, when the grid is built).
  NearestLiveParticle(const Clusters& clusters, const std::vector<glm::vec3>& seeds)
      : clusters_(clusters), seeds_(seeds) {}

  // The particle, or kInvalidIndex when no live seed lies within rho; `d2` its squared distance.
  std::uint32_t find(const glm::vec3& at, float& d2) {
    const float radius = clusters_.radius();
    std::uint32_t best = kInvalidIndex;
    float best_d2 = radius * radius;
    auto consider = [&](std::uint32_t p) {
      if (clusters_.members(p).empty()) return;
      const float e2 = distance2(at, clusters_.seed(p));
      if (e2 < best_d2 || (e2 == best_d2 && (best == kInvalidIndex || p > best))) best_d2 = e2, best = p;
    };
    if (!grid_) {
      std::vector<std::uint32_t> live;
      for (std::uint32_t p = 0; p < clusters_.particle_slots(); ++p)
        if (!clusters_.members(p).empty()) live.push_back(p);
      grid_.emplace(seeds_, live, radius);
    }
    grid_->for_each_near(at, radius, consider);
    for (std::uint32_t p : created_) consider(p);
    d2 = best_d2;
    return best;
  }
  void created(std::uint32_t p) { created_.push_back(p); }

 private:
  const Clusters& clusters_;
  const std::vector<glm::vec3>& seeds_;
  std::optional<PointGrid> grid_;
  std::vector<std::uint32_t> created_;
};

// Brings the member list `m` of particle `p` in line with the rows: `m` is a sorted prefix (the
// members before this apply) followed by the vertices that joined; vertices whose row no longer
// names `p` leave.
void follow_rows(std::vector<std::uint32_t>& m, std::uint32_t p, const Clusters& clusters) {
  const auto tail = std::is_sorted_until(m.begin(), m.end());
  std::sort(tail, m.end());
  std::inplace_merge(m.begin(), tail, m.end());
  m.erase(std::unique(m.begin(), m.end()), m.end());
  m.erase(std::remove_if(m.begin(), m.end(),
                         [&](std::uint32_t v) {
                           for (const Influence& in : clusters.influences(VertexId(v)))
                             if (in.particle == p) return false;
                           return true;
                         }),
          m.end());
}

// Checks apply's arguments before anything changes (a throw leaves the clusters as they were):
// the rest positions, the mesh against the `known` vertices of the clusters and the adjacency,
// then the whole log (check_log).
template <class Refs>
void check_apply(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest, const EditLog& log,
                 const Adjacency* adjacency, std::size_t known, const Refs& face_refs) {
  check_rest(mesh, rest, "clusters.apply");
  const std::size_t n = mesh.vertex_count();
  if (n < known)
    throw Error(ErrorCode::InvalidArgument, "clusters.apply: the mesh has " + std::to_string(n) +
                                                " vertices but the clusters know " + std::to_string(known) +
                                                " (compacted? build the clusters again)");
  if (adjacency && adjacency->vertex_count() > n)
    throw Error(ErrorCode::InvalidArgument, "clusters.apply: the adjacency has more vertices than the mesh");
  check_log(mesh, rest, log, face_refs);
}

// The particles an apply revisits: a flag per particle slot and the list, in the order touched.
struct TouchedParticles {
  explicit TouchedParticles(std::size_t slots) : is_touched(slots, 0) {}
  // `slots`: the particle slots now (p may be a particle created since the last touch).
  void touch(std::uint32_t p, std::size_t slots) {
    if (p >= is_touched.size()) is_touched.resize(slots, 0);
    if (!is_touched[p]) {
      is_touched[p] = 1;
      list.push_back(p);
    }
  }
  std::vector<std::uint8_t> is_touched;
  std::vector<std::uint32_t> list;
};

}  // namespace

std::vector<std::uint32_t> Clusters::replay_log(const EditLog& log) {
  std::vector<std::uint32_t> touched_vertices;
  std::vector<Influence> acc;
  for (const Edit& edit : log.edits) {
    if (const auto* e = std::get_if<VertexAdded>(&edit)) {
      blend_influences(*e, *this, acc);
      set_row(e->v.index, acc.data(), acc.size());
      for (const Influence& in : acc) members_[in.particle].push_back(e->v.index);
      touched_vertices.push_back(e->v.index);
    } else if (const auto* s = std::get_if<VertexSplit>(&edit)) {
      const InfluenceRange from = influences(s->original);
      acc.assign(from.begin(), from.end());
      set_row(s->copy.index, acc.data(), acc.size());
      for (const Influence& in : acc) members_[in.particle].push_back(s->copy.index);
      touched_vertices.push_back(s->copy.index);
      touched_vertices.push_back(s->original.index);
    } else if (const auto* m = std::get_if<VertexMoved>(&edit)) {
      touched_vertices.push_back(m->v.index);
    } else if (const auto* fa = std::get_if<FaceAdded>(&edit)) {
      for (const VertexId v : fa->vertices) {
        ++face_refs_[v.index];
        touched_vertices.push_back(v.index);
      }
    } else if (const auto* fr = std::get_if<FaceRemoved>(&edit)) {
      for (const VertexId v : fr->vertices) {
        --face_refs_[v.index];
        touched_vertices.push_back(v.index);
      }
    }
  }
  std::sort(touched_vertices.begin(), touched_vertices.end());
  touched_vertices.erase(std::unique(touched_vertices.begin(), touched_vertices.end()),
                         touched_vertices.end());
  return touched_vertices;
}

// Dead vertices leave; memberships beyond rho go; uncovered vertices find a particle (the
// nearest live particle whose seed is within rho, or a new particle seeded there).
std::vector<std::uint32_t> Clusters::refit_rows(const std::vector<glm::vec3>& rest,
                                                const std::vector<std::uint32_t>& vertices,
                                                std::size_t old_count, ClusterUpdate& update) {
  const float rho2 = radius_ * radius_;
  const float rho2_slack = rho2 * (1.0f + kRadiusSlack) * (1.0f + kRadiusSlack);
  std::vector<std::uint32_t> joined;
  NearestLiveParticle nearest(*this, seeds_);
  for (std::uint32_t v : vertices) {
    Row& r = rows_[v];
    if (face_refs_[v] == 0) {
      if (r.size && v < old_count) ++update.vertices_removed;
      r.size = 0;
      continue;
    }
    // MeshEditor only ever adds new ids, so a vertex the clusters did not know, or knew without
    // influences, is joining now.
    const bool joining = v >= old_count || r.size == 0;
    std::uint32_t kept = 0;
    for (std::uint32_t i = 0; i < r.size; ++i) {
      const Influence in = pool_[r.begin + i];
      if (distance2(rest[v], seeds_[in.particle]) <= rho2_slack && in.weight > 0.0f)
        pool_[r.begin + kept++] = in;
    }
    r.size = kept;
    if (r.size == 0) {
      float best_d2 = 0.0f;
      std::uint32_t best = nearest.find(rest[v], best_d2);
      if (best == kInvalidIndex) {
        best = new_particle(rest[v]);
        best_d2 = 0.0f;
        update.created.push_back({best, kInvalidIndex});
        nearest.created(best);
      }
      const Influence in{best, falloff(best_d2, rho2)};
      set_row(v, &in, 1);
      members_[best].push_back(v);
      joined.push_back(best);
    }
    renormalise(v);
    if (joining) ++update.vertices_added;
  }
  return joined;
}

ClusterUpdate Clusters::apply(const SurfaceMesh& mesh, const EditLog& log, const Adjacency* adjacency) {
  return apply(mesh, mesh.positions(), log, adjacency);
}

ClusterUpdate Clusters::apply(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest, const EditLog& log,
                              const Adjacency* adjacency) {
  // 0. Check everything before changing anything (a throw leaves the clusters as they were).
  check_apply(mesh, rest, log, adjacency, rows_.size(), face_refs_);
  const std::size_t old_count = rows_.size();
  rows_.resize(mesh.vertex_count(), Row{});
  face_refs_.resize(mesh.vertex_count(), 0);
  ClusterUpdate update;

  // 1. Walk the log: rows for new vertices, live-face counts, the vertices to revisit.
  const std::vector<std::uint32_t> touched_vertices = replay_log(log);

  // 2. The particles to revisit: every particle of a touched vertex (before any removal).
  TouchedParticles touched(seeds_.size());
  for (std::uint32_t v : touched_vertices)
    for (const Influence& in : influences(VertexId(v))) touched.touch(in.particle, seeds_.size());

  // 3. Dead vertices leave; memberships beyond rho go; uncovered vertices find a particle, which
  // is touched too.
  for (std::uint32_t p : refit_rows(rest, touched_vertices, old_count, update))
    touched.touch(p, seeds_.size());

  // 4. Member lists of touched particles follow the rows. Each list is a sorted prefix (the
  // members before this apply) followed by the vertices that joined.
  for (std::uint32_t p : touched.list) follow_rows(members_[p], p, *this);

  // 5. No particle may keep disconnected parts.
  const std::size_t created_before = update.created.size();
  if (adjacency)
    update.particles_split = split_disconnected(
        touched.list, FacesAroundParticles(mesh, *adjacency, *this, touched.list, touched.is_touched),
        update.created);
  else
    update.particles_split = split_disconnected(touched.list, AllFaces(mesh), update.created);
  for (std::size_t i = created_before; i < update.created.size(); ++i)
    touched.touch(update.created[i].particle, seeds_.size());

  // 6. Rest centres of touched particles only.
  for (std::uint32_t p : touched.list) recompute_centre(p, rest);
  std::sort(touched.list.begin(), touched.list.end());
  update.touched = std::move(touched.list);
  if (pool_garbage_ > 1024 && pool_garbage_ * 2 > pool_.size()) compact_pool();
  return update;
}

}  // namespace deepcut
