// SPDX-License-Identifier: MIT
// The faces near the cylinder, and old vertices a hair from its side slid onto it (the stages of
// the rim insertion before any edge is split).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <tuple>

#include "deepcut/core/parallel.h"
#include "ops/common/vertex_slots.h"
#include "ops/drill/rim_insertion.h"

namespace deepcut::drill {
namespace {

// Fewest faces of the grid's answer judged per parallel chunk.
constexpr std::size_t kMinCandidateGrain = 512;

}  // namespace

std::vector<FaceId> find_candidates(const SurfaceMesh& mesh, const CylinderFrame& cyl,
                                    const PosedOverlay& posed, const TriangleGrid& index) {
  std::vector<FaceId> candidates;
  const double eps = cyl.eps;
  // Far enough to hold every face around a vertex snap_shallow_vertices may move.
  const double reach =
      cyl.r + std::max(2.0 * eps, (kSnapBand + 0.01) * 2.0 * cyl.r * std::sin(geometry::kPi / cyl.samples));
  // A centre whose squared distance from the axis lies this far within reach squared is within
  // reach after the square root's rounding (a margin far above a few roundings), so within reach
  // plus the face's radius: most candidates (those inside the cylinder) skip the radius.
  const double surely_near2 = reach * reach * (1.0 - 1e-9);
  auto near_axis = [&](const Triangle& t) {
    const glm::dvec3 p0 = posed(t[0]), p1 = posed(t[1]), p2 = posed(t[2]);
    const glm::dvec3 c = (p0 + p1 + p2) / 3.0;
    const double sv = std::clamp(cyl.s(c), 0.0, cyl.len);
    const glm::dvec3 closest = cyl.a + sv * cyl.d;
    const double dist2 = glm::dot(c - closest, c - closest);  // glm::length squares the same way
    if (dist2 <= surely_near2) return true;
    const double rad =
        std::sqrt(std::max({glm::dot(p0 - c, p0 - c), glm::dot(p1 - c, p1 - c), glm::dot(p2 - c, p2 - c)}));
    return std::sqrt(dist2) <= reach + rad;
  };
  const std::vector<FaceId> near =
      index.query_capsule(glm::vec3(cyl.a), glm::vec3(cyl.a + cyl.len * cyl.d), static_cast<float>(reach));
  // Each face judged on its own (in parallel chunks), then kept in the grid's order.
  std::vector<std::uint8_t> keep(near.size(), 0);
  parallel_for(near.size(), grain_per_thread(near.size(), kMinCandidateGrain), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const FaceId f = near[i];
      keep[i] = f.index < mesh.face_slots() && !mesh.is_deleted(f) && near_axis(mesh.face(f));
    }
  });
  candidates.reserve(near.size());
  for (std::size_t i = 0; i < near.size(); ++i)
    if (keep[i]) candidates.push_back(near[i]);
  return candidates;
}

namespace {

// A corner of a candidate at an old vertex within the snapping band: (vertex, face, candidate),
// sorted by vertex then face (the face decides the order of the sums over a vertex's faces).
using BandCorner = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;

// The corners of the candidates at old vertices within kSnapBand rim spacings of the side and
// between the ends (`in_band`), sorted, and per candidate (`deep_corners`) bit k set when its
// corner k lies deep inside (deep_vertex, before any vertex moves). Each old vertex is judged
// once (the scratch map remembers old vertices only); a new one would be judged at each of its
// corners, but there is none yet when the snap runs.
template <class InBand>
std::vector<BandCorner> band_corners(const SurfaceMesh& mesh, const CylinderFrame& cyl,
                                     const PosedOverlay& posed, const std::vector<FaceId>& candidates,
                                     const InBand& in_band, std::vector<std::uint8_t>& deep_corners) {
  std::vector<BandCorner> corners;
  deep_corners.assign(candidates.size(), 0);
  detail::VertexSlots& judged = detail::VertexSlots::scratch();  // each vertex: bit 0 in the band, bit 1 deep
  judged.reset(posed.first_new());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const FaceId f = candidates[c];
    const Triangle& t = mesh.face(f);
    std::uint8_t deep = 0;
    for (int k = 0; k < 3; ++k) {
      const VertexId v = t[k];
      std::uint32_t b = judged.get(v.index);
      if (b == detail::VertexSlots::kNone) {
        // As deep_vertex judges it (nothing has moved yet: cyl.sd is sd_of these terms).
        const glm::dvec3 p = posed(v);
        const double sv = cyl.s(p), off = cyl.rho(p) - cyl.r;
        b = (in_band(sv, off) && v.index < posed.first_new() ? 1u : 0u) |
            (cyl.deep_sd(cyl.sd_of(sv, off)) ? 2u : 0u);
        if (v.index < posed.first_new()) judged.set(v.index, b);
      }
      if (b & 1u) corners.emplace_back(v.index, f.index, static_cast<std::uint32_t>(c));
      if (b & 2u) deep |= static_cast<std::uint8_t>(1u << k);
    }
    deep_corners[c] = deep;
  }
  std::sort(corners.begin(), corners.end());
  return corners;
}

// Where the snapping slides an old vertex: its new posed and bind positions.
struct Slide {
  glm::dvec3 target;
  glm::vec3 moved;
};

// Slides old vertices a hair from the cylinder's side onto it (snap_shallow_vertices), one at a
// time in vertex order.
class Snapper {
 public:
  Snapper(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed)
      : mesh_(editor.mesh()), editor_(editor), cyl_(cyl), posed_(posed) {
    spacing_ = 2.0 * cyl.r * std::sin(geometry::kPi / cyl.samples);
    band_ = kSnapBand * spacing_;
    close_ = kSnapClose * spacing_;
  }
  void run(const std::vector<FaceId>& candidates, std::vector<std::uint8_t>& deep_corners);

 private:
  bool on_border(VertexId x, const BandCorner* first, const BandCorner* last);
  bool two_near(const glm::dvec3& p) const;
  std::optional<Slide> slide(VertexId x, const BandCorner* first, const BandCorner* last) const;
  bool keeps_faces(VertexId x, const Slide& s, const BandCorner* first, const BandCorner* last) const;

  const SurfaceMesh& mesh_;
  MeshEditor& editor_;
  const CylinderFrame& cyl_;
  PosedOverlay& posed_;
  double spacing_ = 0.0, band_ = 0.0, close_ = 0.0;
  std::vector<VertexId> ring_;                   // x's neighbours (on_border)
  std::array<std::vector<VertexId>, 2> border_;  // edges ahead of / behind x in its faces
};

// A vertex on the mesh's border stays where it is: primitives split at a material seam keep a
// copy of each seam vertex each, and sliding one copy alone would open a crack along the seam.
// It is on the border when an edge from it has a face on one side only. Otherwise ring_ gets its
// neighbours (the faces' corners other than x), each once: with the edges ahead and behind
// alike, those ahead are all of them (x itself only in a face holding it twice).
bool Snapper::on_border(VertexId x, const BandCorner* first, const BandCorner* last) {
  std::vector<VertexId>& ahead = border_[0];
  std::vector<VertexId>& behind = border_[1];
  ahead.clear();
  behind.clear();
  for (const BandCorner* c = first; c != last; ++c) {
    const Triangle& t = mesh_.face(FaceId(std::get<1>(*c)));
    const int q = t[0] == x ? 0 : t[1] == x ? 1 : 2;
    ahead.push_back(t[(q + 1) % 3]);
    behind.push_back(t[(q + 2) % 3]);
  }
  std::sort(ahead.begin(), ahead.end());
  std::sort(behind.begin(), behind.end());
  if (ahead != behind) return true;
  ring_.assign(ahead.begin(), ahead.end());
  ring_.erase(std::unique(ring_.begin(), ring_.end()), ring_.end());
  ring_.erase(std::remove(ring_.begin(), ring_.end(), x), ring_.end());
  return false;
}

// Whether the crossings that two or more edges from a vertex at posed position p to its
// neighbours (ring_) would get lie near it (entering from outside, leaving from inside).
bool Snapper::two_near(const glm::dvec3& p) const {
  const double off = cyl_.rho(p) - cyl_.r;
  const glm::dvec3 m = cyl_.perp(p);
  int near = 0;
  for (VertexId y : ring_) {
    const glm::dvec3 q = posed_(y), k = cyl_.perp(q) - m;
    const double a = glm::dot(k, k), b = glm::dot(m, k), cq = glm::dot(m, m) - cyl_.r * cyl_.r;
    const double disc = b * b - a * cq;
    if (!(a > 0.0) || disc < 0.0) continue;
    const double tt = off > 0.0 ? (-b - std::sqrt(disc)) / a : (-b + std::sqrt(disc)) / a;
    near += tt > 0.0 && tt < 1.0 && tt * glm::length(q - p) < close_;
  }
  return near >= 2;
}

// The slide of x (its faces' corners [first, last)) in its tangent plane onto the cylinder, when
// it is short, keeps x between the ends and moves its bind position.
std::optional<Slide> Snapper::slide(VertexId x, const BandCorner* first, const BandCorner* last) const {
  const glm::dvec3 p = posed_(x), m = cyl_.perp(p);
  glm::dvec3 normal(0.0);
  for (const BandCorner* c = first; c != last; ++c) {
    const Triangle& t = mesh_.face(FaceId(std::get<1>(*c)));
    normal += glm::cross(posed_(t[1]) - posed_(t[0]), posed_(t[2]) - posed_(t[0]));
  }
  const double nl = glm::length(normal);
  if (!(nl > 0.0)) return std::nullopt;
  normal /= nl;
  const glm::dvec3 radial = m / glm::length(m);
  glm::dvec3 dir = radial - glm::dot(radial, normal) * normal;
  const double dl = glm::length(dir);
  if (dl < 0.5) return std::nullopt;  // the surface runs along the cylinder there: no slide reaches it
  dir /= dl;
  const glm::dvec3 k = dir - glm::dot(dir, cyl_.d) * cyl_.d;
  const double a = glm::dot(k, k), b = glm::dot(m, k), cq = glm::dot(m, m) - cyl_.r * cyl_.r;
  const double disc = b * b - a * cq;
  if (!(a > 0.0) || disc < 0.0) return std::nullopt;
  const double l1 = (-b - std::sqrt(disc)) / a, l2 = (-b + std::sqrt(disc)) / a;
  const double step = std::abs(l1) < std::abs(l2) ? l1 : l2;
  if (!(std::abs(step) <= 2.0 * band_)) return std::nullopt;
  const glm::dvec3 target = p + step * dir;
  const double st = cyl_.s(target);
  if (st < spacing_ || st > cyl_.len - spacing_) return std::nullopt;
  const glm::vec3 bind = mesh_.position(x);
  glm::dvec3 shift = target - p;
  if (posed_.unpose())
    shift = glm::dvec3(posed_.unpose()(mesh_, x, glm::vec3(target))) -
            glm::dvec3(posed_.unpose()(mesh_, x, glm::vec3(p)));
  const glm::vec3 moved = glm::vec3(glm::dvec3(bind) + shift);
  if (!(std::isfinite(moved.x) && std::isfinite(moved.y) && std::isfinite(moved.z)) || moved == bind)
    return std::nullopt;
  return Slide{target, moved};
}

// Whether every face around x keeps its orientation (and a non-zero area) in posed and in bind
// space when x slides as `s` says.
bool Snapper::keeps_faces(VertexId x, const Slide& s, const BandCorner* first, const BandCorner* last) const {
  for (const BandCorner* c = first; c != last; ++c) {
    const Triangle& t = mesh_.face(FaceId(std::get<1>(*c)));
    glm::dvec3 pp[3], pn[3], bp[3], bn[3];
    for (int q = 0; q < 3; ++q) {
      pp[q] = posed_(t[q]);
      pn[q] = t[q] == x ? s.target : pp[q];
      bp[q] = glm::dvec3(mesh_.position(t[q]));
      bn[q] = glm::dvec3(t[q] == x ? s.moved : mesh_.position(t[q]));
    }
    for (int space = 0; space < 2; ++space) {
      const glm::dvec3* o = space == 0 ? pp : bp;
      const glm::dvec3* n = space == 0 ? pn : bn;
      const glm::dvec3 before = glm::cross(o[1] - o[0], o[2] - o[0]),
                       after = glm::cross(n[1] - n[0], n[2] - n[0]);
      const double longest = std::max({glm::dot(n[1] - n[0], n[1] - n[0]), glm::dot(n[2] - n[1], n[2] - n[1]),
                                       glm::dot(n[0] - n[2], n[0] - n[2])});
      if (!(glm::length(after) > 1e-9 * longest &&
            glm::dot(before, after) > 0.5 * glm::length(before) * glm::length(after)))
        return false;
    }
  }
  return true;
}

void Snapper::run(const std::vector<FaceId>& candidates, std::vector<std::uint8_t>& deep_corners) {
  // Within the band of the side and between the ends, as the vertex lies before any slide.
  auto in_band = [&](double sv, double off) {
    return !(sv < spacing_ || sv > cyl_.len - spacing_ || std::abs(off) > band_ ||
             std::abs(off) <= 1e-9 * cyl_.r);
  };
  // Every face around a vertex within the band of the side is a candidate (the reach covers it).
  const std::vector<BandCorner> corners =
      band_corners(mesh_, cyl_, posed_, candidates, in_band, deep_corners);
  for (std::size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && std::get<0>(corners[j]) == std::get<0>(corners[i])) ++j;
    const VertexId x(std::get<0>(corners[i]));
    const BandCorner *first = corners.data() + i, *last = corners.data() + j;
    if (on_border(x, first, last) || !two_near(posed_(x))) continue;
    const std::optional<Slide> s = slide(x, first, last);
    if (!s || !keeps_faces(x, *s, first, last)) continue;
    editor_.move_vertex(x, s->moved);
    posed_.move(x, s->target);  // in index order: the corners are sorted
    // Its faces' deep corners follow (as deep_vertex judges the moved vertex).
    const auto bit = static_cast<std::uint8_t>(deep_vertex(cyl_, posed_, x) ? 1u : 0u);
    for (const BandCorner* c = first; c != last; ++c) {
      const Triangle& t = mesh_.face(FaceId(std::get<1>(*c)));
      std::uint8_t& deep = deep_corners[std::get<2>(*c)];
      for (int k = 0; k < 3; ++k)
        if (t[k] == x) deep = static_cast<std::uint8_t>((deep & ~(1u << k)) | (bit << k));
    }
  }
}

}  // namespace

// An old vertex lying just inside (or just outside) the cylinder leaves the crossings of two of
// its edges a hair apart: the far corners of its faces fan to those two close rim points (needles
// under a degree), or it stays as the tip of a sliver between them. Such a vertex, within
// kSnapBand rim spacings of the side, is slid in its tangent plane onto the cylinder before any
// edge is split, so it becomes a rim vertex itself and its edges are not cut there. Only where
// every face around it keeps its orientation (and a non-zero area) in posed and in bind space;
// the bind position moves by the vertex's own skinning inverted (the unposer), so the edit is a
// VertexMoved in the log and the new posed position is reported (DrillResult::moved).
void snap_shallow_vertices(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed,
                           const std::vector<FaceId>& candidates, std::vector<std::uint8_t>& deep_corners) {
  Snapper(editor, cyl, posed).run(candidates, deep_corners);
}
}  // namespace deepcut::drill
