// SPDX-License-Identifier: MIT
#include "deepcut/core/spatial_index.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <cmath>
#include <limits>
#include <string>

#include "deepcut/core/parallel.h"
#include "sorted_ids.h"

namespace deepcut {

namespace {

constexpr std::size_t kGrain = 32768;

struct Extent {
  BoundingBox bounds;
  double extent_sum = 0.0;
  std::size_t faces = 0;
};

}  // namespace

// The packed cell lists, in parallel: cell sizes counted with atomic increments, a prefix sum,
// faces scattered with atomic cursors, then each cell's list sorted, so every cell lists its faces
// in increasing order (what a serial fill in face order gives) whatever the thread count.
template <class CellsOf>
void TriangleGrid::fill_cells(std::size_t slots, CellsOf&& cells_of) {
  const std::size_t cells = static_cast<std::size_t>(dims_.x) * dims_.y * dims_.z;
  std::unique_ptr<std::atomic<std::uint32_t>[]> cursor(new std::atomic<std::uint32_t>[cells]);
  parallel_for(cells, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) cursor[c].store(0, std::memory_order_relaxed);
  });
  parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f)
      cells_of(f, [&](std::size_t c) { cursor[c].fetch_add(1, std::memory_order_relaxed); });
  });
  start_.assign(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) {
    start_[c + 1] = start_[c] + cursor[c].load(std::memory_order_relaxed);
    cursor[c].store(start_[c], std::memory_order_relaxed);
  }
  faces_.resize(start_[cells]);
  parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f)
      cells_of(f, [&](std::size_t c) {
        faces_[cursor[c].fetch_add(1, std::memory_order_relaxed)] = static_cast<std::uint32_t>(f);
      });
  });
  parallel_for(cells, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) std::sort(faces_.begin() + start_[c], faces_.begin() + start_[c + 1]);
  });
}

TriangleGrid TriangleGrid::build(const SurfaceMesh& mesh, const std::vector<glm::vec3>& points,
                                 float cell_size) {
  if (points.size() != mesh.vertex_count())
    throw Error(ErrorCode::InvalidArgument, "spatial index: " + std::to_string(points.size()) +
                                                " positions for " + std::to_string(mesh.vertex_count()) +
                                                " vertices");
  TriangleGrid grid;
  const auto& tris = mesh.faces();
  const std::size_t slots = tris.size();
  auto face_box = [&](const Triangle& t) {
    const glm::vec3 &a = points[t[0].index], &b = points[t[1].index], &c = points[t[2].index];
    BoundingBox box;
    box.min = glm::min(a, glm::min(b, c));
    box.max = glm::max(a, glm::max(b, c));
    return box;
  };
  const Extent extent = parallel_reduce(
      slots, kGrain, Extent(),
      [&](std::size_t b, std::size_t e) {
        Extent part;
        for (std::size_t f = b; f < e; ++f) {
          if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
          const BoundingBox box = face_box(tris[f]);
          part.bounds.add(box);
          const glm::vec3 d = box.max - box.min;
          part.extent_sum += std::max({d.x, d.y, d.z});
          ++part.faces;
        }
        return part;
      },
      [](Extent acc, const Extent& part) {
        acc.bounds.add(part.bounds);
        acc.extent_sum += part.extent_sum;
        acc.faces += part.faces;
        return acc;
      });
  grid.bounds_ = extent.bounds;
  const std::size_t faces = extent.faces;
  grid.alive_.assign(slots, 0);
  grid.tris_ = tris;
  grid.placed_ = points;
  if (faces == 0) return grid;
  const glm::vec3 size =
      glm::max(grid.bounds_.max - grid.bounds_.min, glm::vec3(1e-6f * (grid.bounds_.diagonal() + 1.0f)));
  float cell = cell_size > 0.0f ? cell_size : static_cast<float>(2.0 * extent.extent_sum / double(faces));
  // At most about one cell per face (and never a degenerate cell).
  const double volume = double(size.x) * size.y * size.z;
  const double min_cell = std::cbrt(volume / double(faces + 64));
  cell = std::max(cell, static_cast<float>(min_cell));
  if (!(cell > 0.0f)) cell = std::max({size.x, size.y, size.z});
  grid.cell_ = cell;
  grid.origin_ = grid.bounds_.min;
  grid.dims_ = glm::max(glm::ivec3(glm::ceil(size / cell)), glm::ivec3(1));

  // Cell range of every live face (parallel), then a counting sort into the packed lists.
  struct Range {
    glm::ivec3 lo, hi;
  };
  std::vector<Range> range(slots);
  parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) {
        range[f] = {glm::ivec3(0), glm::ivec3(-1)};
        continue;
      }
      const BoundingBox box = face_box(tris[f]);
      range[f] = {grid.cell_of(box.min), grid.cell_of(box.max)};
    }
  });
  grid.fill_cells(slots, [&](std::size_t f, auto&& visit) {
    const Range& r = range[f];
    for (int z = r.lo.z; z <= r.hi.z; ++z)
      for (int y = r.lo.y; y <= r.hi.y; ++y)
        for (int x = r.lo.x; x <= r.hi.x; ++x) visit(grid.cell_index(x, y, z));
  });
  parallel_for(slots, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) grid.alive_[f] = range[f].hi.x >= range[f].lo.x ? 1 : 0;
  });
  grid.live_ = faces;
  return grid;
}

std::uint64_t TriangleGrid::layout_hash() const {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  add(&bounds_, sizeof(bounds_));
  add(&cell_, sizeof(cell_));
  add(&dims_, sizeof(dims_));
  add(start_.data(), start_.size() * sizeof(std::uint32_t));
  add(faces_.data(), faces_.size() * sizeof(std::uint32_t));
  add(alive_.data(), alive_.size());
  add(&live_, sizeof(live_));
  return h;
}

glm::ivec3 TriangleGrid::cell_of(const glm::vec3& p) const {
  const glm::vec3 q = (p - origin_) / cell_;
  glm::ivec3 c;
  for (int i = 0; i < 3; ++i) {
    // Negative, NaN and infinite coordinates go to cell 0, those past the end to the last cell
    // (what clamping floor(q) gives, without the library calls: this runs for every face).
    const float v = q[i];
    if (!(v >= 0.0f) || v == std::numeric_limits<float>::infinity())
      c[i] = 0;
    else if (v >= float(dims_[i] - 1))
      c[i] = dims_[i] - 1;
    else
      c[i] = static_cast<int>(v);
  }
  return c;
}

void TriangleGrid::insert(FaceId f, const Triangle& t, const std::vector<glm::vec3>& points) {
  if (f.index >= alive_.size()) alive_.resize(f.index + 1, 0);
  if (alive_[f.index]) return;
  alive_[f.index] = 1;
  ++live_;
  if (f.index >= tris_.size()) tris_.resize(f.index + 1);
  tris_[f.index] = t;
  file(f, t, points);
}

void TriangleGrid::file(FaceId f, const Triangle& t, const std::vector<glm::vec3>& points) {
  BoundingBox b;
  for (auto v : t) b.add(points[v.index]);
  const glm::ivec3 lo = cell_of(b.min), hi = cell_of(b.max);
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) added_[cell_index(x, y, z)].push_back(f.index);
}

void TriangleGrid::reserve(std::size_t faces, std::size_t vertices) {
  alive_.reserve(faces);
  tris_.reserve(faces);
  placed_.reserve(vertices);
}

void TriangleGrid::apply(const EditLog& log, const std::vector<glm::vec3>& points) {
  if (empty()) return;
  std::vector<VertexId> moved;
  for (const Edit& e : log.edits) {
    if (const auto* r = std::get_if<FaceRemoved>(&e)) {
      if (r->f.index < alive_.size() && alive_[r->f.index]) {
        alive_[r->f.index] = 0;
        --live_;
      }
    } else if (const auto* a = std::get_if<FaceAdded>(&e)) {
      insert(a->f, a->vertices, points);
    } else if (const auto* m = std::get_if<VertexMoved>(&e)) {
      // A vertex made by this log has only faces the log adds (filed at `points` above).
      if (m->v.index < placed_.size() && m->v.index < points.size()) moved.push_back(m->v);
    }
  }
  std::sort(moved.begin(), moved.end());
  moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
  // Every face using v has v's old place inside its box: it is filed in that place's cell. Those
  // still live are filed again over their new box (a superset stays a superset). Each old cell
  // is visited once (a tear moves a row of lip vertices that share cells).
  std::vector<std::size_t> cells;
  cells.reserve(moved.size());
  for (const VertexId v : moved) {
    const glm::ivec3 c = cell_of(placed_[v.index]);
    cells.push_back(cell_index(c.x, c.y, c.z));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  auto is_moved = [&](VertexId v) { return std::binary_search(moved.begin(), moved.end(), v); };
  std::vector<FaceId> near;
  for (const std::size_t c : cells) collect_cell(c, near);
  sort_unique(near);
  for (const FaceId f : near) {
    const Triangle& t = tris_[f.index];
    if (is_moved(t[0]) || is_moved(t[1]) || is_moved(t[2])) file(f, t, points);
  }
  const std::size_t before = placed_.size();
  if (points.size() > before) placed_.insert(placed_.end(), points.begin() + static_cast<std::ptrdiff_t>(before), points.end());
  for (const VertexId v : moved) placed_[v.index] = points[v.index];
}

void TriangleGrid::truncate(std::size_t faces, std::size_t vertices) {
  for (std::size_t f = faces; f < alive_.size(); ++f)
    if (alive_[f]) {
      alive_[f] = 0;
      --live_;
    }
  if (placed_.size() > vertices) placed_.resize(vertices);
}

void TriangleGrid::sort_unique(std::vector<FaceId>& v) { detail::sort_unique_ids(v); }

template <class Fn>
void TriangleGrid::for_each_live_in_cell(std::size_t c, Fn&& fn) const {
  for (std::uint32_t i = start_[c]; i < start_[c + 1]; ++i)
    if (alive_[faces_[i]]) fn(faces_[i]);
  if (added_.empty()) return;
  const auto it = added_.find(c);
  if (it == added_.end()) return;
  for (const std::uint32_t f : it->second)
    if (alive_[f]) fn(f);
}

void TriangleGrid::collect_cell(std::size_t c, std::vector<FaceId>& out) const {
  for_each_live_in_cell(c, [&](std::uint32_t f) { out.push_back(FaceId(f)); });
}

void TriangleGrid::collect(int x, int y, int z0, int z1, std::vector<FaceId>& out) const {
  for (int z = z0; z <= z1; ++z) collect_cell(cell_index(x, y, z), out);
}

std::vector<FaceId> TriangleGrid::query_box(const BoundingBox& box) const {
  std::vector<FaceId> out;
  if (empty() || box.empty()) return out;
  const glm::ivec3 lo = cell_of(box.min), hi = cell_of(box.max);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) collect(x, y, lo.z, hi.z, out);
  sort_unique(out);
  return out;
}

std::vector<FaceId> TriangleGrid::query_points(const std::vector<glm::vec3>& points) const {
  std::vector<FaceId> out;
  if (empty() || points.empty()) return out;
  std::vector<std::size_t> cells;
  cells.reserve(points.size());
  for (const glm::vec3& p : points) {
    const glm::ivec3 c = cell_of(p);
    cells.push_back(cell_index(c.x, c.y, c.z));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (std::size_t c : cells) collect_cell(c, out);
  sort_unique(out);
  return out;
}

// The cells' live faces are marked (detail::IdMarks) and read back in order.
std::vector<FaceId> TriangleGrid::query_capsule(const glm::vec3& a, const glm::vec3& b, float radius) const {
  std::vector<FaceId> out;
  if (empty()) return out;
  detail::IdMarks marks(0, static_cast<std::uint32_t>(std::max<std::size_t>(alive_.size(), 1) - 1));
  const auto mark_column = [&](int x, int y, int z0, int z1) {
    for (int z = z0; z <= z1; ++z)
      for_each_live_in_cell(cell_index(x, y, z), [&](std::uint32_t f) { marks.mark(f); });
  };
  BoundingBox box;
  box.add(glm::min(a, b) - glm::vec3(radius));
  box.add(glm::max(a, b) + glm::vec3(radius));
  const glm::ivec3 lo = cell_of(box.min), hi = cell_of(box.max);
  // Column by column (x, y): the part of the segment whose xy projection passes within reach of
  // the column gives the z range to visit.
  const glm::dvec2 a2(a.x, a.y), d2(double(b.x) - a.x, double(b.y) - a.y);
  const double dd = glm::dot(d2, d2);
  const double reach = double(radius) + 0.7072 * double(cell_);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      const glm::dvec2 c(origin_.x + (x + 0.5) * cell_, origin_.y + (y + 0.5) * cell_);
      double t0 = 0.0, t1 = 1.0;
      const glm::dvec2 m = a2 - c;
      if (dd > 0.0) {
        // |m + t d2|^2 <= reach^2
        const double bq = glm::dot(m, d2), cq = glm::dot(m, m) - reach * reach;
        const double disc = bq * bq - dd * cq;
        if (disc < 0.0) continue;
        const double s = std::sqrt(disc);
        t0 = std::max(0.0, (-bq - s) / dd);
        t1 = std::min(1.0, (-bq + s) / dd);
        if (t0 > t1) continue;
      } else if (glm::dot(m, m) > reach * reach) {
        continue;
      }
      const double za = a.z + t0 * (double(b.z) - a.z), zb = a.z + t1 * (double(b.z) - a.z);
      const float zlo = static_cast<float>(std::min(za, zb) - radius),
                  zhi = static_cast<float>(std::max(za, zb) + radius);
      const int cz0 = cell_of(glm::vec3(origin_.x, origin_.y, zlo)).z,
                cz1 = cell_of(glm::vec3(origin_.x, origin_.y, zhi)).z;
      mark_column(x, y, cz0, cz1);
    }
  marks.take(out);
  return out;
}

}  // namespace deepcut

namespace deepcut {

std::vector<FaceId> TriangleGrid::query_slab(const BoundingBox& box, const glm::vec3& point, const glm::vec3& normal,
                                             float half_width) const {
  std::vector<FaceId> out;
  if (empty() || box.empty()) return out;
  const glm::dvec3 n(normal);
  const double len = glm::length(n);
  if (!(len > 0.0) || !std::isfinite(len)) return query_box(box);
  const glm::dvec3 u = n / len;
  const double reach = std::max(0.0, double(half_width));
  const double plane = glm::dot(u, glm::dvec3(point));
  const glm::ivec3 lo = cell_of(box.min), hi = cell_of(box.max);
  // Range of dot(u, p) over one cell. Border cells reach to infinity outward (faces outside the
  // build bounds are filed there), which a non-zero normal component makes unbounded.
  auto axis_range = [&](int axis, int i, double& mn, double& mx) {
    const double a = double(origin_[axis]) + double(i) * cell_, b = a + cell_;
    const bool open_lo = i == 0, open_hi = i == dims_[axis] - 1;
    const double c = u[axis];
    if (c == 0.0) {
      mn = mx = 0.0;
      return;
    }
    const double inf = std::numeric_limits<double>::infinity();
    const double va = open_lo ? (c > 0.0 ? -inf : inf) : c * a, vb = open_hi ? (c > 0.0 ? inf : -inf) : c * b;
    mn = std::min(va, vb);
    mx = std::max(va, vb);
  };
  std::vector<double> xmn(hi.x - lo.x + 1), xmx(hi.x - lo.x + 1);
  for (int x = lo.x; x <= hi.x; ++x) axis_range(0, x, xmn[x - lo.x], xmx[x - lo.x]);
  for (int y = lo.y; y <= hi.y; ++y) {
    double ymn, ymx;
    axis_range(1, y, ymn, ymx);
    for (int z = lo.z; z <= hi.z; ++z) {
      double zmn, zmx;
      axis_range(2, z, zmn, zmx);
      for (int x = lo.x; x <= hi.x; ++x) {
        const double mn = xmn[x - lo.x] + ymn + zmn, mx = xmx[x - lo.x] + ymx + zmx;
        if (mn - plane > reach || plane - mx > reach) continue;
        collect_cell(cell_index(x, y, z), out);
      }
    }
  }
  sort_unique(out);
  return out;
}

}  // namespace deepcut
