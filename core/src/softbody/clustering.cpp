// SPDX-License-Identifier: MIT
#include "deepcut/core/softbody/clustering.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "csr_fill.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
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
        throw Error(ErrorCode::InvalidArgument,
                    "clusters.apply: the log removes face " + std::to_string(fr->f.index) +
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
      auto it = std::find_if(acc.begin(), acc.end(), [&](const Influence& a) { return a.particle == in.particle; });
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

// The live faces around the members of the touched particles, each visited once without a
// visited set: a vertex is visited from its first touched particle, a face from its first such
// vertex.
class FacesAroundParticles {
 public:
  FacesAroundParticles(const SurfaceMesh& mesh, const Adjacency& adjacency, const Clusters& clusters,
                       const std::vector<std::uint32_t>& touched, const std::vector<std::uint8_t>& is_touched)
      : mesh_(mesh), adjacency_(adjacency), clusters_(clusters), touched_(touched), is_touched_(is_touched) {}

  template <class Fn>
  void operator()(Fn&& fn) const {
    for (std::uint32_t p : touched_)
      for (std::uint32_t v : clusters_.members(p)) {
        if (v >= adjacency_.vertex_count() || first_touched(v) != p) continue;
        for (const FaceId f : adjacency_.vertex_faces(VertexId(v))) {
          const Triangle& t = mesh_.face(f);
          std::uint32_t first = kInvalidIndex;
          for (int k = 0; k < 3 && first == kInvalidIndex; ++k)
            if (first_touched(t[k].index) != kInvalidIndex) first = t[k].index;
          if (first == v) fn(t);
        }
      }
  }

 private:
  std::uint32_t first_touched(std::uint32_t v) const {
    for (const Influence& in : clusters_.influences(VertexId(v)))
      if (in.particle < is_touched_.size() && is_touched_[in.particle]) return in.particle;
    return kInvalidIndex;
  }

  const SurfaceMesh& mesh_;
  const Adjacency& adjacency_;
  const Clusters& clusters_;
  const std::vector<std::uint32_t>& touched_;
  const std::vector<std::uint8_t>& is_touched_;
};

// ------------------------------------------------------------------------------------------------
// Pieces of Clusters::split_disconnected. `Rows` and `Pool` are its rows_ and pool_ (types
// private to Clusters, deduced here).

// A part of a split particle other than its largest: it leaves the particle.
struct Minor {
  std::uint32_t particle;
  std::vector<std::uint32_t> vertices;  // sorted
  std::vector<std::uint32_t> entries;   // their pool entries for `particle`
};

// Groups each listed particle's members by root (`root_of(v, p)`: the union-find root of v's
// entry for p); the largest part keeps the particle (its list in `members`), the others are
// appended to `minors` in order. Each particle's parts in parallel (disjoint members and pool
// entries), gathered in order. Returns how many particles were disconnected.
template <class RootOf>
std::size_t group_parts(const std::vector<std::uint32_t>& particles,
                        std::vector<std::vector<std::uint32_t>>& members, RootOf&& root_of,
                        std::vector<Minor>& minors) {
  std::vector<Parts> split(particles.size());
  std::vector<std::uint8_t> is_split(particles.size(), 0);
  parallel_for(particles.size(), 4, [&](std::size_t b, std::size_t e) {
    std::vector<std::uint32_t> roots;  // of the members, in order
    PartsScratch scratch;
    for (std::size_t k = b; k < e; ++k) {
      const std::uint32_t p = particles[k];
      const auto& m = members[p];
      if (m.size() < 2) continue;
      roots.resize(m.size());
      bool single = true;
      for (std::size_t i = 0; i < m.size(); ++i) {
        roots[i] = root_of(m[i], p);
        single = single && roots[i] == roots[0];
      }
      if (single) continue;
      is_split[k] = 1;
      split[k] = parts_by_group(m, roots, scratch);
    }
  });
  std::size_t split_count = 0;
  for (std::size_t k = 0; k < particles.size(); ++k) {
    if (!is_split[k]) continue;
    ++split_count;
    for (auto& vertices : split[k].minors) minors.push_back({particles[k], std::move(vertices), {}});
    members[particles[k]] = std::move(split[k].main);
  }
  return split_count;
}

// Fills each part's pool entries (`entry_of(v, p)`) and decides which parts are dropped: a part
// whose every vertex keeps a main-part influence elsewhere (1), any other becomes a particle of
// its own (0). The writes are to disjoint pool entries, part by part.
template <class Rows, class Pool, class EntryOf>
std::vector<std::uint8_t> parts_to_drop(std::vector<Minor>& minors, const Rows& rows, const Pool& pool,
                                        EntryOf&& entry_of) {
  // The pool entries of the parts' vertices, marked by entry.
  detail::UninitVector<std::uint8_t> minor_entry(pool.size());
  parallel_for(pool.size(), 1 << 16, [&](std::size_t b, std::size_t e) {
    std::fill(minor_entry.begin() + b, minor_entry.begin() + e, std::uint8_t(0));
  });
  parallel_for(minors.size(), 1, [&](std::size_t k, std::size_t) {
    Minor& part = minors[k];
    part.entries.resize(part.vertices.size());
    for (std::size_t i = 0; i < part.vertices.size(); ++i)
      minor_entry[part.entries[i] = entry_of(part.vertices[i], part.particle)] = 1;
  });
  std::vector<std::uint8_t> drop(minors.size(), 1);
  parallel_for(minors.size(), 1, [&](std::size_t k, std::size_t) {
    for (std::uint32_t v : minors[k].vertices) {
      const auto& r = rows[v];
      bool has_main = false;
      for (std::uint32_t i = 0; i < r.size && !has_main; ++i)
        has_main = pool[r.begin + i].particle != minors[k].particle && !minor_entry[r.begin + i];
      if (!has_main) {
        drop[k] = 0;
        break;
      }
    }
  });
  return drop;
}

// The rows the split fixes when few vertices are listed: the renamed and the dropped ones, each
// sorted and unique.
void list_rows_to_fix(const std::vector<Minor>& minors, const std::vector<std::uint8_t>& drop,
                      std::vector<std::uint32_t>& renamed, std::vector<std::uint32_t>& dropped) {
  for (std::size_t k = 0; k < minors.size(); ++k) {
    auto& to = drop[k] ? dropped : renamed;
    to.insert(to.end(), minors[k].vertices.begin(), minors[k].vertices.end());
  }
  for (auto* v : {&renamed, &dropped}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
}

// Many listed vertices (a build): a mark per row in `mark` (1 renamed, 2 dropped), then one pass
// over the rows, each row fixed once, by one thread.
template <class SortRow, class LoseDropped>
void fix_marked_rows(std::atomic<std::uint8_t>* mark, std::size_t row_count, const std::vector<Minor>& minors,
                     const std::vector<std::uint8_t>& drop, SortRow&& sort_row, LoseDropped&& lose_dropped) {
  parallel_for(row_count, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) mark[v].store(0, std::memory_order_relaxed);
  });
  parallel_for(minors.size(), 1, [&](std::size_t k, std::size_t) {
    const std::uint8_t bit = drop[k] ? 2 : 1;
    for (const std::uint32_t v : minors[k].vertices) mark[v].fetch_or(bit, std::memory_order_relaxed);
  });
  parallel_for(row_count, 1 << 14, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const std::uint8_t m = mark[v].load(std::memory_order_relaxed);
      if (m & 1) sort_row(static_cast<std::uint32_t>(v));
      if (m & 2) lose_dropped(static_cast<std::uint32_t>(v));
    }
  });
}

// Few: the rows of list_rows_to_fix, renamed first (a row's entries end sorted whatever the
// order of the two).
template <class SortRow, class LoseDropped>
void fix_listed_rows(const std::vector<std::uint32_t>& renamed, const std::vector<std::uint32_t>& dropped,
                     SortRow&& sort_row, LoseDropped&& lose_dropped) {
  parallel_for(renamed.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) sort_row(renamed[i]);
  });
  parallel_for(dropped.size(), 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) lose_dropped(dropped[i]);
  });
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Small helpers on rows and particles.

void Clusters::set_row(std::uint32_t v, const Influence* first, std::size_t count) {
  Row& r = rows_[v];
  if (count > r.capacity) {
    pool_garbage_ += r.capacity;
    r.begin = static_cast<std::uint32_t>(pool_.size());
    r.capacity = static_cast<std::uint32_t>(count);
    pool_.resize(pool_.size() + count);
  }
  std::copy(first, first + count, pool_.begin() + r.begin);
  r.size = static_cast<std::uint32_t>(count);
  sort_row(v);
}

void Clusters::sort_row(std::uint32_t v) {
  const Row& r = rows_[v];
  Influence* row = pool_.data() + r.begin;
  // Rows are short: insertion sort.
  for (std::uint32_t i = 1; i < r.size; ++i)
    for (std::uint32_t j = i; j > 0 && row[j].particle < row[j - 1].particle; --j)
      std::swap(row[j], row[j - 1]);
}

void Clusters::compact_pool() {
  decltype(pool_) pool;
  pool.reserve(pool_.size() - pool_garbage_);
  for (Row& r : rows_) {
    const auto b = static_cast<std::uint32_t>(pool.size());
    pool.insert(pool.end(), pool_.begin() + r.begin, pool_.begin() + r.begin + r.size);
    r.begin = b;
    r.capacity = r.size;
  }
  pool_.swap(pool);
  pool_garbage_ = 0;
}

void Clusters::renormalise(std::uint32_t v) {
  const Row& r = rows_[v];
  double sum = 0.0;
  for (std::uint32_t i = 0; i < r.size; ++i) sum += pool_[r.begin + i].weight;
  for (std::uint32_t i = 0; i < r.size; ++i) {
    Influence& e = pool_[r.begin + i];
    e.weight = sum > 0.0 ? static_cast<float>(e.weight / sum) : 1.0f / float(r.size);
  }
}

void Clusters::recompute_centre(std::uint32_t p, const std::vector<glm::vec3>& rest) {
  const auto& m = members_[p];
  if (m.empty()) {
    centres_[p] = seeds_[p];
    return;
  }
  glm::dvec3 sum(0.0);
  for (std::uint32_t v : m) sum += glm::dvec3(rest[v]);
  centres_[p] = glm::vec3(sum / double(m.size()));
}

std::uint32_t Clusters::new_particle(const glm::vec3& seed_ref) {
  // Copy first: callers pass seeds_[i], which seeds_.push_back may reallocate (ASan found the
  // read of the freed seed in centres_.push_back).
  const glm::vec3 seed = seed_ref;
  const auto p = static_cast<std::uint32_t>(seeds_.size());
  seeds_.push_back(seed);
  centres_.push_back(seed);
  members_.emplace_back();
  return p;
}

std::size_t Clusters::particle_count() const {
  std::size_t n = 0;
  for (const auto& m : members_) n += m.empty() ? 0 : 1;
  return n;
}

// ------------------------------------------------------------------------------------------------
// Splitting particles into connected parts.

template <class ForEachFace>
std::size_t Clusters::split_disconnected(const std::vector<std::uint32_t>& particles,
                                         ForEachFace&& for_each_face,
                                         std::vector<ClusterUpdate::NewParticle>& created) {
  if (particles.empty()) return 0;
  auto entry_of = [&](std::uint32_t v, std::uint32_t p) {
    const Row& r = rows_[v];
    for (std::uint32_t i = 0; i < r.size; ++i)
      if (pool_[r.begin + i].particle == p) return r.begin + i;
    throw Error(ErrorCode::InvariantViolated, "clusters: vertex " + std::to_string(v) +
                                                  " is listed in particle " + std::to_string(p) +
                                                  " but has no influence from it");
  };
  std::vector<std::uint8_t> in_set(seeds_.size(), 0);
  for (std::uint32_t p : particles) in_set[p] = 1;

  // Union-find over the pool entries (one per vertex-in-particle) of the listed particles. The
  // smaller root always wins, so each part's root is its smallest entry whatever the order of
  // the unions: `for_each_face` may call its function from several threads at once.
  ConcurrentUnionFind uf(pool_.size());
  auto find = [&](std::uint32_t x) { return uf.find(x); };
  for_each_face([&](const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k].index, b = t[(k + 1) % 3].index;
      if (a == b) continue;
      // Rows are sorted by particle: walk both at once.
      const Row& ra = rows_[a];
      const Row& rb = rows_[b];
      std::uint32_t i = ra.begin, j = rb.begin;
      const std::uint32_t ie = ra.begin + ra.size, je = rb.begin + rb.size;
      while (i < ie && j < je) {
        const std::uint32_t pa = pool_[i].particle, pb = pool_[j].particle;
        if (pa < pb) {
          ++i;
        } else if (pb < pa) {
          ++j;
        } else {
          if (in_set[pa]) uf.unite(i, j);
          ++i;
          ++j;
        }
      }
    }
  });

  // Group each particle's members by root; the largest part keeps the particle.
  std::vector<Minor> minors;
  const std::size_t split_count = group_parts(
      particles, members_, [&](std::uint32_t v, std::uint32_t p) { return find(entry_of(v, p)); }, minors);
  if (minors.empty()) return split_count;

  // Every pass below runs over the pool, part by part or row by row (a build splits thousands of
  // parts): the writes are to disjoint pool entries, and each row is fixed by one thread.
  // A dropped part's vertices keep a main-part influence elsewhere; any other part becomes a
  // particle of its own (same seed, so the radius invariant holds), numbered in order.
  const std::vector<std::uint8_t> drop = parts_to_drop(minors, rows_, pool_, entry_of);
  // Everything the row fixing below needs is allocated before any entry is renamed, so that a
  // failed allocation leaves the clusters as they were. Many listed vertices (a build): a mark
  // per vertex, then one pass over the rows instead of sorting the lists on this thread; few:
  // the renamed and dropped vertices, sorted and unique.
  std::size_t listed = 0;
  for (const Minor& part : minors) listed += part.vertices.size();
  const bool marked = listed * 16 >= rows_.size();
  std::unique_ptr<std::atomic<std::uint8_t>[]> mark;
  std::vector<std::uint32_t> renamed, dropped;
  if (marked)
    mark.reset(new std::atomic<std::uint8_t>[rows_.size()]);
  else
    list_rows_to_fix(minors, drop, renamed, dropped);
  std::vector<std::uint32_t> renamed_to(minors.size(), kInvalidIndex);
  for (std::size_t k = 0; k < minors.size(); ++k)
    if (!drop[k]) {
      renamed_to[k] = new_particle(seeds_[minors[k].particle]);
      created.push_back({renamed_to[k], minors[k].particle});
    }
  parallel_for(minors.size(), 1, [&](std::size_t k, std::size_t) {
    for (const std::uint32_t e : minors[k].entries) pool_[e].particle = renamed_to[k];
  });
  // Rows with a renamed entry are sorted again; rows with a dropped one lose it and are
  // renormalised (a row's entries end sorted whatever the order of the two). A vertex may lie in
  // several parts: each row is fixed once, by one thread.
  auto lose_dropped = [&](std::uint32_t v) {
    Row& r = rows_[v];
    std::uint32_t n = 0;
    for (std::uint32_t j = 0; j < r.size; ++j)
      if (pool_[r.begin + j].particle != kInvalidIndex) pool_[r.begin + n++] = pool_[r.begin + j];
    r.size = n;
    renormalise(v);
  };
  auto resort = [&](std::uint32_t v) { sort_row(v); };
  if (marked)
    fix_marked_rows(mark.get(), rows_.size(), minors, drop, resort, lose_dropped);
  else
    fix_listed_rows(renamed, dropped, resort, lose_dropped);
  for (std::size_t k = 0; k < minors.size(); ++k)
    if (!drop[k]) members_[renamed_to[k]] = std::move(minors[k].vertices);
  return split_count;
}

// ------------------------------------------------------------------------------------------------
// Build.

// Every vertex of `ids` belongs to each particle whose seed lies within rho of it. Rows are built
// per vertex from a grid over the seeds (count, prefix sum, fill), member lists per particle by
// turning the rows over (a counting sort by particle, in vertex order); every write is to a
// disjoint range: the result does not depend on the thread count.
void Clusters::build_memberships(const std::vector<glm::vec3>& rest,
                                 const UnfilledVector<std::uint32_t>& ids) {
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
      assert(n == count && "build_memberships: the fill and the count pass disagree");
      std::sort(out, out + n, [](const Influence& a, const Influence& x) { return a.particle < x.particle; });
      rows_[v] = Row{start[i], n, count};
      renormalise(v);
    }
  });
  // Member lists: the rows turned over (a vertex is within rho of a seed exactly when the seed
  // is within rho of it: distance2 is symmetric), ascending by vertex as `ids` is.
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
  // Every row empty (written over the pool; build_memberships fills the live vertices' rows).
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
  c.build_memberships(rest, ids);
  c.centres_ = c.seeds_;

  std::vector<std::uint32_t> all(particles);
  for (std::uint32_t p = 0; p < particles; ++p) all[p] = p;
  std::vector<ClusterUpdate::NewParticle> created;
  // The faces are walked in parallel (split_disconnected's unions do not depend on their order).
  auto for_each_face = [&](auto&& fn) {
    parallel_for(mesh.face_slots(), 8192, [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f < e; ++f) {
        const FaceId id(static_cast<std::uint32_t>(f));
        if (!mesh.is_deleted(id)) fn(mesh.face(id));
      }
    });
  };
  c.split_disconnected(all, for_each_face, created);
  parallel_for(c.seeds_.size(), 8, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) c.recompute_centre(static_cast<std::uint32_t>(p), rest);
  });
  return c;
}

// ------------------------------------------------------------------------------------------------
// Apply an edit log.

ClusterUpdate Clusters::apply(const SurfaceMesh& mesh, const EditLog& log, const Adjacency* adjacency) {
  return apply(mesh, mesh.positions(), log, adjacency);
}

ClusterUpdate Clusters::apply(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest, const EditLog& log,
                              const Adjacency* adjacency) {
  check_rest(mesh, rest, "clusters.apply");
  const std::size_t n = mesh.vertex_count();
  if (n < rows_.size())
    throw Error(ErrorCode::InvalidArgument,
                "clusters.apply: the mesh has " + std::to_string(n) + " vertices but the clusters know " +
                    std::to_string(rows_.size()) + " (compacted? build the clusters again)");
  if (adjacency && adjacency->vertex_count() > n)
    throw Error(ErrorCode::InvalidArgument, "clusters.apply: the adjacency has more vertices than the mesh");
  // 0. Check the whole log before changing anything (a throw leaves the clusters as they were).
  check_log(mesh, rest, log, face_refs_);

  const std::size_t old_count = rows_.size();
  rows_.resize(n, Row{});
  face_refs_.resize(n, 0);
  ClusterUpdate update;
  const float rho2 = radius_ * radius_;
  const float rho2_slack = rho2 * (1.0f + kRadiusSlack) * (1.0f + kRadiusSlack);

  // 1. Walk the log: rows for new vertices, live-face counts, the vertices to revisit.
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

  // 2. The particles to revisit: every particle of a touched vertex (before any removal).
  std::vector<std::uint8_t> is_touched(seeds_.size(), 0);
  std::vector<std::uint32_t> touched;
  auto touch = [&](std::uint32_t p) {
    if (p >= is_touched.size()) is_touched.resize(seeds_.size(), 0);
    if (!is_touched[p]) {
      is_touched[p] = 1;
      touched.push_back(p);
    }
  };
  for (std::uint32_t v : touched_vertices)
    for (const Influence& in : influences(VertexId(v))) touch(in.particle);

  // 3. Dead vertices leave; memberships beyond rho go; uncovered vertices find a particle.
  NearestLiveParticle nearest(*this, seeds_);
  for (std::uint32_t v : touched_vertices) {
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
      // The nearest live particle whose seed is within rho, or a new particle seeded here.
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
      touch(best);
    }
    renormalise(v);
    if (joining) ++update.vertices_added;
  }

  // 4. Member lists of touched particles follow the rows. Each list is a sorted prefix (the
  // members before this apply) followed by the vertices that joined.
  for (std::uint32_t p : touched) follow_rows(members_[p], p, *this);

  // 5. No particle may keep disconnected parts.
  const std::size_t created_before = update.created.size();
  if (adjacency) {
    update.particles_split = split_disconnected(
        touched, FacesAroundParticles(mesh, *adjacency, *this, touched, is_touched), update.created);
  } else {
    update.particles_split = split_disconnected(
        touched, [&](auto&& fn) { mesh.for_each_face([&](FaceId, const Triangle& t) { fn(t); }); },
        update.created);
  }
  for (std::size_t i = created_before; i < update.created.size(); ++i) touch(update.created[i].particle);

  // 6. Rest centres of touched particles only.
  for (std::uint32_t p : touched) recompute_centre(p, rest);
  std::sort(touched.begin(), touched.end());
  update.touched = std::move(touched);
  if (pool_garbage_ > 1024 && pool_garbage_ * 2 > pool_.size()) compact_pool();
  return update;
}

}  // namespace deepcut
