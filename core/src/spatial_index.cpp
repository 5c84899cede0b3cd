// SPDX-License-Identifier: MIT
#include "deepcut/core/spatial_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "csr_fill.h"
#include "deepcut/core/parallel.h"
#include "parallel_beside.h"
#include "sorted_ids.h"
#include "uninit_vector.h"

namespace deepcut {

namespace {

constexpr std::size_t kGrain = 32768;

struct Extent {
  BoundingBox bounds;
  double extent_sum = 0.0;
  std::size_t faces = 0;
};

inline BoundingBox face_box(const std::vector<glm::vec3>& points, const Triangle& t) {
  const glm::vec3 &a = points[t[0].index], &b = points[t[1].index], &c = points[t[2].index];
  BoundingBox box;
  box.min = glm::min(a, glm::min(b, c));
  box.max = glm::max(a, glm::max(b, c));
  return box;
}

// The bounds and the summed largest extents of the live faces, folded in chunk order, with
// `beside()` run beside the chunks (detail::parallel_reduce_beside).
template <class Beside>
Extent face_extent(const SurfaceMesh& mesh, const std::vector<glm::vec3>& points, Beside&& beside) {
  const auto& tris = mesh.faces();
  return detail::parallel_reduce_beside(
      tris.size(), kGrain, Extent(),
      [&](std::size_t b, std::size_t e) {
        Extent part;
        for (std::size_t f = b; f < e; ++f) {
          if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
          const BoundingBox box = face_box(points, tris[f]);
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
      },
      beside);
}

// The cells a face goes to: the box of cells from cell `lo`, `d` more along each axis.
// Trivial (no member initialisers), so that an UninitVector of them is left unwritten when sized.
struct FaceCells {
  enum Kind : std::uint8_t { kNone, kBox, kWide };
  std::uint32_t lo;
  std::uint8_t d[3];
  Kind kind;

  static FaceCells of(const glm::ivec3& lo, const glm::ivec3& hi, std::size_t lo_index) {
    FaceCells s{};
    const glm::ivec3 d = hi - lo;
    if (d.x < 0 || d.y < 0 || d.z < 0) {
      s.kind = kNone;  // NaN corners: in no cell
    } else if (d.x > 255 || d.y > 255 || d.z > 255 || lo_index > 0xffffffffu) {
      s.kind = kWide;
    } else {
      s.kind = kBox;
      s.lo = static_cast<std::uint32_t>(lo_index);
      for (int k = 0; k < 3; ++k) s.d[k] = static_cast<std::uint8_t>(d[k]);
    }
    return s;
  }
};

// Calls visit(cell) for the cells from `lo` to `d` more along each axis of a grid of `dims`,
// in increasing order (none when a `d` is negative).
template <class Visit>
void visit_box(std::size_t lo, const glm::ivec3& d, const glm::ivec3& dims, Visit&& visit) {
  for (int z = 0; z <= d.z; ++z)
    for (int y = 0; y <= d.y; ++y) {
      const std::size_t row =
          lo + (std::size_t(z) * std::size_t(dims.y) + std::size_t(y)) * std::size_t(dims.x);
      for (int x = 0; x <= d.x; ++x) visit(row + std::size_t(x));
    }
}

// The cell edge: `cell_size`, or 0 for about two mean face extents; at most about one cell per
// face (and never a degenerate cell) in a box of `size`.
float grid_cell(const Extent& extent, const glm::vec3& size, float cell_size) {
  const std::size_t faces = extent.faces;
  float cell = cell_size > 0.0f ? cell_size : static_cast<float>(2.0 * extent.extent_sum / double(faces));
  const double volume = double(size.x) * size.y * size.z;
  const double min_cell = std::cbrt(volume / double(faces + 64));
  cell = std::max(cell, static_cast<float>(min_cell));
  if (!(cell > 0.0f)) cell = std::max({size.x, size.y, size.z});
  return cell;
}

// The cell holding `p` in a grid of `dims` cells of edge `cell` from `origin`: what
// TriangleGrid::cell_of returns, inlined into the build's loop over the faces.
inline glm::ivec3 grid_cell_of(const glm::vec3& p, const glm::vec3& origin, float cell,
                               const glm::ivec3& dims) {
  const glm::vec3 q = (p - origin) / cell;
  glm::ivec3 c;
  for (int i = 0; i < 3; ++i) {
    // Negative, NaN and infinite coordinates go to cell 0, those past the end to the last cell
    // (what clamping floor(q) gives, without the library calls: this runs for every face).
    const float v = q[i];
    if (!(v >= 0.0f) || v == std::numeric_limits<float>::infinity())
      c[i] = 0;
    else if (v >= float(dims[i] - 1))
      c[i] = dims[i] - 1;
    else
      c[i] = static_cast<int>(v);
  }
  return c;
}

// Where the build places faces: the grid's origin, cell edge and cell counts.
struct GridFrame {
  glm::vec3 origin;
  float cell;
  glm::ivec3 dims;

  // The cells of the corners of face `t`'s box.
  void range(const std::vector<glm::vec3>& points, const Triangle& t, glm::ivec3& lo, glm::ivec3& hi) const {
    const BoundingBox box = face_box(points, t);
    lo = grid_cell_of(box.min, origin, cell, dims);
    hi = grid_cell_of(box.max, origin, cell, dims);
  }
  // TriangleGrid::cell_index.
  std::size_t index(const glm::ivec3& c) const {
    return (static_cast<std::size_t>(c.z) * static_cast<std::size_t>(dims.y) +
            static_cast<std::size_t>(c.y)) *
               static_cast<std::size_t>(dims.x) +
           static_cast<std::size_t>(c.x);
  }
};

// The cell pass: each face's cells into spans[f] (found once: grid_cell_of divides), its corners
// copied into tris_out[f] and its live flag into alive[f], every face written; `beside()` run
// beside the chunks. A NaN corner can put a box's x range backwards: such a face (counted live
// by the extent pass) is filed in no cell and marked dead (as the grid always did).
template <class Beside>
void face_cells(const SurfaceMesh& mesh, const std::vector<glm::vec3>& points, const GridFrame& frame,
                Triangle* tris_out, std::uint8_t* alive, FaceCells* spans, Beside&& beside) {
  const auto& tris = mesh.faces();
  detail::parallel_for_beside(
      tris.size(), kGrain,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t f = b; f < e; ++f) {
          tris_out[f] = tris[f];
          spans[f] = FaceCells{};
          alive[f] = 0;
          if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
          glm::ivec3 lo, hi;
          frame.range(points, tris[f], lo, hi);
          spans[f] = FaceCells::of(lo, hi, frame.index(lo));
          alive[f] = hi.x >= lo.x;
        }
      },
      beside);
}

}  // namespace

TriangleGrid TriangleGrid::build(const SurfaceMesh& mesh, const std::vector<glm::vec3>& points,
                                 float cell_size) {
  if (points.size() != mesh.vertex_count())
    throw Error(ErrorCode::InvalidArgument, "spatial index: " + std::to_string(points.size()) +
                                                " positions for " + std::to_string(mesh.vertex_count()) +
                                                " vertices");
  TriangleGrid grid;
  const auto& tris = mesh.faces();
  const std::size_t slots = tris.size();
  // The grid's copies of the corners and positions, and its live flags, are std::vectors: each
  // is sized or copied on one thread, their pages faulted in over the pool first. Those serial
  // fills run beside the passes over the faces (usually the calling thread takes them while the
  // others share the chunks), not before them: the flags and corners are sized beside the extent
  // pass (the cell pass, which reads every face's corners, writes both), the positions copied
  // beside the cell pass.
  detail::reserve_prefaulted(grid.alive_, slots, 0);
  detail::reserve_prefaulted(grid.tris_, slots, 0);
  detail::reserve_prefaulted(grid.placed_, points.size(), 0);
  const Extent extent = face_extent(mesh, points, [&] {
    grid.alive_.resize(slots);
    grid.tris_.resize(slots);
  });
  grid.bounds_ = extent.bounds;
  const std::size_t faces = extent.faces;
  if (faces == 0) {
    std::copy(tris.begin(), tris.end(), grid.tris_.begin());
    grid.placed_.assign(points.begin(), points.end());
    return grid;
  }
  const glm::vec3 size =
      glm::max(grid.bounds_.max - grid.bounds_.min, glm::vec3(1e-6f * (grid.bounds_.diagonal() + 1.0f)));
  const float cell = grid_cell(extent, size, cell_size);
  grid.cell_ = cell;
  grid.origin_ = grid.bounds_.min;
  grid.dims_ = glm::max(glm::ivec3(glm::ceil(size / cell)), glm::ivec3(1));

  // The cells of each live face, kept in 8 bytes for the fill's two passes; a face over more
  // than 256 cells along an axis is found again instead.
  const GridFrame frame{grid.origin_, cell, grid.dims_};
  detail::UninitVector<FaceCells> spans(slots);
  face_cells(mesh, points, frame, grid.tris_.data(), grid.alive_.data(), spans.data(),
             [&] { grid.placed_.assign(points.begin(), points.end()); });
  const std::size_t cells = static_cast<std::size_t>(grid.dims_.x) * grid.dims_.y * grid.dims_.z;
  detail::fill_csr(slots, cells, grid.start_, grid.faces_, [&](std::size_t f, auto&& visit) {
    const FaceCells& s = spans[f];
    if (s.kind == FaceCells::kNone) return;
    std::size_t first = s.lo;
    glm::ivec3 d(s.d[0], s.d[1], s.d[2]);
    if (s.kind == FaceCells::kWide) {
      glm::ivec3 lo, hi;
      frame.range(points, tris[f], lo, hi);
      first = frame.index(lo);
      d = hi - lo;
    }
    visit_box(first, d, grid.dims_, visit);
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

glm::ivec3 TriangleGrid::cell_of(const glm::vec3& p) const { return grid_cell_of(p, origin_, cell_, dims_); }

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
