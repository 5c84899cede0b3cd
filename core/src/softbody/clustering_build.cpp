// SPDX-License-Identifier: MIT
// Soft-body clusters: Clusters::build. The seeds come from clustering_seeds.cpp, the split into
// connected parts from clustering_split.cpp; here the live vertices, the rows and the member
// lists of a fresh build.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <memory>
#include <string>

#include "csr_fill.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/softbody/clustering.h"
#include "softbody/clustering_detail.h"
#include "softbody/point_grid.h"
#include "uninit_vector.h"

namespace deepcut {
namespace {

using namespace clustering_detail;

// The live faces around each vertex, into `out` (empty; sized here, every element written over
// the pool). Counted in parallel with atomic increments: a count does not depend on their order.
template <class Refs>
void count_face_refs(const SurfaceMesh& mesh, Refs& out) {
  const std::size_t n = mesh.vertex_count();
  constexpr std::size_t kGrain = 1 << 15;
  std::unique_ptr<std::atomic<std::uint32_t>[]> refs(new std::atomic<std::uint32_t>[n]);
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) refs[v].store(0, std::memory_order_relaxed);
  });
  parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const FaceId id(static_cast<std::uint32_t>(f));
      if (mesh.is_deleted(id)) continue;
      for (const VertexId v : mesh.face(id)) refs[v.index].fetch_add(1, std::memory_order_relaxed);
    }
  });
  detail::reserve_prefaulted(out, n, 0);
  out.resize(n);
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) out[v] = refs[v].load(std::memory_order_relaxed);
  });
}

// The vertices with a live face, ascending, into `ids` (empty; each placed by a prefix sum over
// the pool, nothing written first on the calling thread). Throws for the smallest one with a
// non-finite rest position.
template <class Refs, class Ids>
void live_vertices(const Refs& face_refs, const std::vector<glm::vec3>& rest, Ids& ids) {
  const std::size_t n = face_refs.size();
  const std::uint32_t bad = parallel_reduce(
      n, 1 << 15, kInvalidIndex,
      [&](std::size_t b, std::size_t e) {
        for (auto v = static_cast<std::uint32_t>(b); v < e; ++v) {
          const glm::vec3& p = rest[v];
          if (face_refs[v] && !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return v;
        }
        return kInvalidIndex;
      },
      [](std::uint32_t a, std::uint32_t b) { return a != kInvalidIndex ? a : b; });
  if (bad != kInvalidIndex)
    throw Error(ErrorCode::InvalidInput,
                "cluster: vertex " + std::to_string(bad) + " has a non-finite position");
  detail::reserve_prefaulted(ids, n, 0);
  ids.resize(n);
  const std::uint32_t live = detail::exclusive_scan(
      n, [&](std::size_t v) { return face_refs[v] ? 1u : 0u; },
      [&](std::size_t v, std::uint32_t at) {
        if (face_refs[v]) ids[at] = static_cast<std::uint32_t>(v);
      });
  ids.resize(live);
}

}  // namespace

// Every vertex of `ids` belongs to each particle whose seed lies within rho of it. Rows are built
// per vertex from a grid over the seeds (count, prefix sum, fill); every write is to a disjoint
// range: the result does not depend on the thread count.
void Clusters::build_rows(const std::vector<glm::vec3>& rest, const UnfilledVector<std::uint32_t>& ids) {
  const float rho = radius_, rho2 = rho * rho;
  // Cells are searched a little wider than rho so that no point within rho (in float) is missed;
  // the exact test below decides.
  const float reach = rho * (1.0f + 1e-4f);
  const auto particles = static_cast<std::uint32_t>(seeds_.size());
  std::vector<std::uint32_t> all(particles);
  for (std::uint32_t p = 0; p < particles; ++p) all[p] = p;
  const PointGrid seed_grid(seeds_, all, rho);
  constexpr std::size_t kGrain = 2048;
  // Each vertex's row length, then in place its row's start (a prefix sum over the pool).
  detail::UninitVector<std::uint32_t> start(ids.size() + 1);
  parallel_for(ids.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const glm::vec3 pv = rest[ids[i]];
      std::uint32_t count = 0;
      seed_grid.for_each_near(pv, reach, [&](std::uint32_t p) { count += distance2(pv, seeds_[p]) <= rho2; });
      start[i] = count;
    }
  });
  start[ids.size()] = detail::exclusive_scan(
      ids.size(), [&](std::size_t i) { return start[i]; },
      [&](std::size_t i, std::uint32_t at) { start[i] = at; });
  // Sized without a fill on this thread: the pass below writes every entry.
  detail::reserve_prefaulted(pool_, std::size_t(start[ids.size()]), 0);
  pool_.resize(start[ids.size()]);
  parallel_for(ids.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t v = ids[i];
      const glm::vec3 pv = rest[v];
      Influence* out = pool_.data() + start[i];
      // The row's length is the count pass's; the fill (the same test) writes no more than that
      // and, should it find fewer, leaves the rest as spare capacity rather than unwritten size.
      const std::uint32_t count = start[i + 1] - start[i];
      std::uint32_t n = 0;
      seed_grid.for_each_near(pv, reach, [&](std::uint32_t p) {
        const float d2 = distance2(pv, seeds_[p]);
        if (d2 <= rho2 && n < count) out[n++] = Influence{p, falloff(d2, rho2)};
      });
      assert(n == count && "build_rows: the fill and the count pass disagree");
      std::sort(out, out + n, [](const Influence& a, const Influence& x) { return a.particle < x.particle; });
      rows_[v] = Row{start[i], n, count};
      renormalise(v);
    }
  });
}

// Member lists: the rows turned over (a vertex is within rho of a seed exactly when the seed is
// within rho of it: distance2 is symmetric), a counting sort by particle, ascending by vertex as
// `ids` is; every write is to a disjoint range.
void Clusters::build_member_lists(const UnfilledVector<std::uint32_t>& ids) {
  const auto particles = static_cast<std::uint32_t>(seeds_.size());
  members_.assign(particles, {});
  auto for_each_particle = [&](std::size_t i, auto&& visit) {
    const Row& r = rows_[ids[i]];
    for (std::uint32_t k = 0; k < r.size; ++k) visit(pool_[r.begin + k].particle);
  };
  constexpr std::size_t kListGrain = 1 << 15;
  const std::size_t chunks = (ids.size() + kListGrain - 1) / kListGrain;
  if (chunks * particles <= std::max(ids.size(), kListGrain)) {
    // Few particles (the usual case): a count per chunk of `ids` and particle, their sums per
    // particle in chunk order (each list sized there, over the pool), then every chunk files its
    // vertices straight into the lists from its own offsets: no packed copy of the lists, whose
    // sizing filled it on this thread.
    detail::UninitVector<std::uint32_t> at(chunks * particles);  // chunk c, particle p: at[c * particles + p]
    parallel_for(ids.size(), kListGrain, [&](std::size_t b, std::size_t e) {
      std::uint32_t* mine = at.data() + (b / kListGrain) * particles;
      std::fill(mine, mine + particles, 0u);
      for (std::size_t i = b; i < e; ++i) for_each_particle(i, [&](std::uint32_t p) { ++mine[p]; });
    });
    parallel_for(particles, 2, [&](std::size_t b, std::size_t e) {
      for (std::size_t p = b; p < e; ++p) {
        std::uint32_t sum = 0;
        for (std::size_t c = 0; c < chunks; ++c) {
          const std::uint32_t count = at[c * particles + p];
          at[c * particles + p] = sum;
          sum += count;
        }
        members_[p].resize(sum);
      }
    });
    parallel_for(ids.size(), kListGrain, [&](std::size_t b, std::size_t e) {
      std::uint32_t* mine = at.data() + (b / kListGrain) * particles;
      for (std::size_t i = b; i < e; ++i)
        for_each_particle(i, [&](std::uint32_t p) { members_[p][mine[p]++] = ids[i]; });
    });
    return;
  }
  std::vector<std::uint32_t> first, member;
  detail::fill_csr(ids.size(), particles, first, member, for_each_particle);
  parallel_for(particles, 2, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      members_[p].resize(first[p + 1] - first[p]);
      for (std::uint32_t k = first[p]; k < first[p + 1]; ++k) members_[p][k - first[p]] = ids[member[k]];
    }
  });
}

Clusters Clusters::build(const SurfaceMesh& mesh, const ClusterOptions& options) {
  return build(mesh, mesh.positions(), options);
}

Clusters Clusters::build(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest,
                         const ClusterOptions& options) {
  check_radius(options.radius, "cluster");
  if (!(options.cover_fraction > 0.0f && options.cover_fraction <= 1.0f))
    throw Error(ErrorCode::InvalidArgument,
                "cluster: cover fraction must lie in (0, 1], got " + std::to_string(options.cover_fraction));
  check_rest(mesh, rest, "cluster");
  Clusters c;
  c.radius_ = options.radius;
  const std::size_t n = mesh.vertex_count();
  // Every row empty (written over the pool; build_rows fills the live vertices' rows).
  detail::reserve_prefaulted(c.rows_, n, 0);
  c.rows_.resize(n);
  parallel_for(n, 1 << 15, [&](std::size_t b, std::size_t e) {
    std::fill(c.rows_.begin() + b, c.rows_.begin() + e, Row{});
  });
  count_face_refs(mesh, c.face_refs_);
  UnfilledVector<std::uint32_t> ids;
  live_vertices(c.face_refs_, rest, ids);
  if (ids.empty()) return c;

  const float rho = options.radius;
  const PointGrid grid(rest, ids, rho);
  const std::vector<std::uint32_t> seeds =
      farthest_point_seeds(rest, ids.data(), ids.size(), grid, rho * options.cover_fraction);

  const auto particles = static_cast<std::uint32_t>(seeds.size());
  c.seeds_.resize(particles);
  for (std::uint32_t p = 0; p < particles; ++p) c.seeds_[p] = rest[seeds[p]];
  c.build_rows(rest, ids);
  c.build_member_lists(ids);
  c.centres_ = c.seeds_;

  std::vector<std::uint32_t> all(particles);
  for (std::uint32_t p = 0; p < particles; ++p) all[p] = p;
  std::vector<ClusterUpdate::NewParticle> created;
  // The faces are walked in parallel (split_disconnected's unions do not depend on their order).
  c.split_disconnected(all, AllFacesParallel(mesh), created);
  parallel_for(c.seeds_.size(), 8, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) c.recompute_centre(static_cast<std::uint32_t>(p), rest);
  });
  return c;
}

}  // namespace deepcut
