// SPDX-License-Identifier: MIT
// Soft-body clusters: Clusters::split_disconnected, which splits particles into their connected
// parts (after a build, and after an apply for the particles it touched). Compiled here for the
// three face walkers of clustering_detail.h.
#include <algorithm>
#include <atomic>
#include <memory>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/softbody/clustering.h"
#include "softbody/clustering_detail.h"
#include "uninit_vector.h"

namespace deepcut {
namespace {

using namespace clustering_detail;

// The steps of Clusters::split_disconnected. `Rows` and `Pool` are its rows_ and pool_ (types
// private to Clusters, deduced here).

// Unites, for each edge of the faces `for_each_face` walks, the two ends' pool entries of every
// particle both ends belong to and `listed` marks. The smaller root always wins
// (ConcurrentUnionFind), so each part's root is its smallest entry whatever the order of the
// unions: `for_each_face` may call its function from several threads at once.
template <class Rows, class Pool, class ForEachFace>
void unite_shared_entries(const Rows& rows, const Pool& pool, const std::vector<std::uint8_t>& listed,
                          ForEachFace& for_each_face, ConcurrentUnionFind& uf) {
  for_each_face([&](const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k].index, b = t[(k + 1) % 3].index;
      if (a == b) continue;
      // Rows are sorted by particle: walk both at once.
      const auto& ra = rows[a];
      const auto& rb = rows[b];
      std::uint32_t i = ra.begin, j = rb.begin;
      const std::uint32_t ie = ra.begin + ra.size, je = rb.begin + rb.size;
      while (i < ie && j < je) {
        const std::uint32_t pa = pool[i].particle, pb = pool[j].particle;
        if (pa < pb) {
          ++i;
        } else if (pb < pa) {
          ++j;
        } else {
          if (listed[pa]) uf.unite(i, j);
          ++i;
          ++j;
        }
      }
    }
  });
}

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

// The rows the split fixes, chosen and allocated (rows_to_fix) before any entry is renamed, so
// that a failed allocation leaves the clusters as they were. Many listed vertices (a build): a
// mark per row, then one pass over the rows instead of sorting the lists on this thread; few:
// the renamed and the dropped vertices, each sorted and unique.
struct RowsToFix {
  bool marked = false;
  std::unique_ptr<std::atomic<std::uint8_t>[]> mark;  // marked: one per row
  std::vector<std::uint32_t> renamed, dropped;        // not marked
};

RowsToFix rows_to_fix(const std::vector<Minor>& minors, const std::vector<std::uint8_t>& drop,
                      std::size_t row_count) {
  RowsToFix fix;
  std::size_t listed = 0;
  for (const Minor& part : minors) listed += part.vertices.size();
  fix.marked = listed * 16 >= row_count;
  if (fix.marked) {
    fix.mark.reset(new std::atomic<std::uint8_t>[row_count]);
    return fix;
  }
  for (std::size_t k = 0; k < minors.size(); ++k) {
    auto& to = drop[k] ? fix.dropped : fix.renamed;
    to.insert(to.end(), minors[k].vertices.begin(), minors[k].vertices.end());
  }
  for (auto* v : {&fix.renamed, &fix.dropped}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return fix;
}

// Marked: a mark per row (1 renamed, 2 dropped), then one pass over the rows, each row fixed
// once, by one thread.
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

// Not marked: the listed rows, renamed first (a row's entries end sorted whatever the order of
// the two).
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

template <class Minors>
void Clusters::rename_minor_parts(Minors& minors, const std::vector<std::uint8_t>& drop,
                                  std::vector<ClusterUpdate::NewParticle>& created) {
  const RowsToFix fix = rows_to_fix(minors, drop, rows_.size());
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
  if (fix.marked)
    fix_marked_rows(fix.mark.get(), rows_.size(), minors, drop, resort, lose_dropped);
  else
    fix_listed_rows(fix.renamed, fix.dropped, resort, lose_dropped);
  for (std::size_t k = 0; k < minors.size(); ++k)
    if (!drop[k]) members_[renamed_to[k]] = std::move(minors[k].vertices);
}

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
  std::vector<std::uint8_t> listed(seeds_.size(), 0);
  for (std::uint32_t p : particles) listed[p] = 1;
  // Union-find over the pool entries (one per vertex-in-particle) of the listed particles.
  ConcurrentUnionFind uf(pool_.size());
  unite_shared_entries(rows_, pool_, listed, for_each_face, uf);

  // Group each particle's members by root; the largest part keeps the particle.
  std::vector<Minor> minors;
  const std::size_t split_count = group_parts(
      particles, members_, [&](std::uint32_t v, std::uint32_t p) { return uf.find(entry_of(v, p)); }, minors);
  if (minors.empty()) return split_count;

  // Every pass below runs over the pool, part by part or row by row (a build splits thousands of
  // parts): the writes are to disjoint pool entries, and each row is fixed by one thread.
  // A dropped part's vertices keep a main-part influence elsewhere; any other part becomes a
  // particle of its own (same seed, so the radius invariant holds), numbered in order.
  const std::vector<std::uint8_t> drop = parts_to_drop(minors, rows_, pool_, entry_of);
  rename_minor_parts(minors, drop, created);
  return split_count;
}

template std::size_t Clusters::split_disconnected<AllFacesParallel>(const std::vector<std::uint32_t>&,
                                                                    AllFacesParallel&&,
                                                                    std::vector<ClusterUpdate::NewParticle>&);
template std::size_t Clusters::split_disconnected<AllFaces>(const std::vector<std::uint32_t>&, AllFaces&&,
                                                            std::vector<ClusterUpdate::NewParticle>&);
template std::size_t Clusters::split_disconnected<FacesAroundParticles>(
    const std::vector<std::uint32_t>&, FacesAroundParticles&&, std::vector<ClusterUpdate::NewParticle>&);

}  // namespace deepcut
