// SPDX-License-Identifier: MIT
#include "deepcut/core/ops/tear.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory_resource>
#include <numeric>
#include <queue>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/spatial_index.h"
#include "ops/common/pinches.h"

namespace deepcut {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A tear's hash maps and sets take their nodes from one arena per tear (a bump allocator freed
// when the tear ends) instead of one malloc and free per node: same containers, same hashing and
// iteration order, so the same results.
template <class K, class V>
using Map = std::pmr::unordered_map<K, V>;
template <class K>
using Set = std::pmr::unordered_set<K>;

std::uint64_t edge_key(VertexId a, VertexId b) {
  const auto lo = std::min(a.index, b.index), hi = std::max(a.index, b.index);
  return (std::uint64_t(lo) << 32) | hi;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// One planar part of the tear surface: a plane and one or two triangles in it, each given by its
// three inward half-planes in the plane's 2D frame (h(q) = dot(q - corner, inward) >= 0 inside).
struct Piece {
  glm::dvec3 origin{0.0}, normal{0.0}, e1{0.0}, e2{0.0};
  std::vector<std::array<glm::dvec2, 3>> corners;  // counter-clockwise in (e1, e2)
  std::vector<std::array<glm::dvec2, 3>> inward;   // unit inward normal of edge k (corner k -> k+1)
  std::vector<std::array<glm::vec3, 3>> world;     // the triangles in world space
  BoundingBox box;

  glm::dvec2 project(const glm::dvec3& p) const {
    return {glm::dot(p - origin, e1), glm::dot(p - origin, e2)};
  }
  std::size_t hcount() const { return 3 * corners.size(); }
};

// Half-plane values of one point against every triangle of a piece (at most two triangles).
using HValues = std::array<double, 6>;

HValues hvalues(const Piece& piece, const glm::dvec2& q) {
  HValues h{};
  for (std::size_t j = 0; j < piece.corners.size(); ++j)
    for (int k = 0; k < 3; ++k) h[3 * j + k] = glm::dot(q - piece.corners[j][k], piece.inward[j][k]);
  return h;
}

bool inside(const Piece& piece, const HValues& h) {
  for (std::size_t j = 0; j < piece.corners.size(); ++j)
    if (h[3 * j] >= 0.0 && h[3 * j + 1] >= 0.0 && h[3 * j + 2] >= 0.0) return true;
  return false;
}

struct Interval {
  double lo, hi;
};

// The parts of the segment a -> b (parameter 0..1) inside the piece, from the endpoints'
// half-plane values (the same values decide inside(a), so the two tests never disagree), merged,
// snapped to the ends within `snap` and without pieces shorter than `snap` (a whole segment is
// always kept).
std::vector<Interval> clip_segment(const Piece& piece, const HValues& ha, const HValues& hb, double snap) {
  std::vector<Interval> raw;
  for (std::size_t j = 0; j < piece.corners.size(); ++j) {
    double lo = 0.0, hi = 1.0;
    bool empty = false;
    for (int k = 0; k < 3 && !empty; ++k) {
      const double a = ha[3 * j + k], b = hb[3 * j + k];
      if (a >= 0.0 && b >= 0.0) continue;
      if (a < 0.0 && b < 0.0) {
        empty = true;
        break;
      }
      const double s = a / (a - b);
      if (a < 0.0)
        lo = std::max(lo, s);
      else
        hi = std::min(hi, s);
    }
    if (!empty && lo <= hi) raw.push_back({lo, hi});
  }
  std::sort(raw.begin(), raw.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  std::vector<Interval> merged;
  for (const Interval& iv : raw) {
    if (!merged.empty() && iv.lo <= merged.back().hi + snap)
      merged.back().hi = std::max(merged.back().hi, iv.hi);
    else
      merged.push_back(iv);
  }
  std::vector<Interval> out;
  for (Interval iv : merged) {
    if (iv.lo < snap) iv.lo = 0.0;
    if (iv.hi > 1.0 - snap) iv.hi = 1.0;
    const bool whole = iv.lo == 0.0 && iv.hi == 1.0;
    if (whole || iv.hi - iv.lo > snap) out.push_back(iv);
  }
  return out;
}

bool in_intervals(const std::vector<Interval>& ivs, double s) {
  for (const Interval& iv : ivs)
    if (s >= iv.lo && s <= iv.hi) return true;
  return false;
}

void check_blade(const Blade& b, const char* which) {
  if (!finite(b.handle) || !finite(b.tip))
    throw Error(ErrorCode::InvalidArgument, std::string("tear: the ") + which + " blade is not finite");
}

Piece make_piece(const glm::dvec3& normal, const glm::dvec3& origin) {
  Piece p;
  p.normal = glm::normalize(normal);
  p.origin = origin;
  const glm::dvec3 axis = std::abs(p.normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  p.e1 = glm::normalize(glm::cross(p.normal, axis));
  p.e2 = glm::cross(p.normal, p.e1);
  return p;
}

// Adds a triangle (world corners, assumed in or projected onto the piece's plane).
void add_triangle(Piece& piece, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                  double min_area2) {
  std::array<glm::dvec2, 3> q = {piece.project(a), piece.project(b), piece.project(c)};
  const double area2 = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[1].y - q[0].y) * (q[2].x - q[0].x);
  if (std::abs(area2) <= min_area2) return;
  if (area2 < 0.0) std::swap(q[1], q[2]);
  std::array<glm::dvec2, 3> m;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 d = q[(k + 1) % 3] - q[k];
    m[k] = glm::normalize(glm::dvec2(-d.y, d.x));
  }
  piece.corners.push_back(q);
  piece.inward.push_back(m);
  std::array<glm::vec3, 3> w;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 p = piece.origin + q[k].x * piece.e1 + q[k].y * piece.e2;
    w[k] = glm::vec3(p);
    piece.box.add(w[k]);
  }
  piece.world.push_back(w);
}

// The tear surface: one piece (planar quad) or two (quad folded along H0-T1).
std::vector<Piece> make_pieces(const Blade& start, const Blade& end) {
  check_blade(start, "start");
  check_blade(end, "end");
  const glm::dvec3 h0(start.handle), t0(start.tip), h1(end.handle), t1(end.tip);
  const double size = std::max({glm::length(t0 - h0), glm::length(t1 - h1), glm::length(h1 - h0),
                                glm::length(t1 - t0), glm::length(t1 - h0), glm::length(h1 - t0)});
  // A blade a million times shorter than the sweep is as degenerate as a zero-length one; say
  // which pose is out of scale (usually a mistyped coordinate) rather than blame the shorter one.
  const double len0 = glm::length(t0 - h0), len1 = glm::length(t1 - h1);
  if (len0 == 0.0 || size == 0.0)
    throw Error(ErrorCode::InvalidArgument, "tear: the start blade has zero length (handle == tip)");
  if (len1 == 0.0)
    throw Error(ErrorCode::InvalidArgument, "tear: the end blade has zero length (handle == tip)");
  if (std::min(len0, len1) <= 1e-6 * size) {
    const auto text = [](double v) {
      std::ostringstream o;
      o << v;
      return o.str();
    };
    const bool start_longer = len0 > len1;
    const double longer = std::max(len0, len1), shorter = std::min(len0, len1);
    if (longer > 1e6 * shorter)
      throw Error(ErrorCode::InvalidArgument,
                  std::string("tear: the ") + (start_longer ? "start" : "end") + " blade (length " + text(longer) +
                      ") is over a million times longer than the " + (start_longer ? "end" : "start") +
                      " blade (length " + text(shorter) + "); check its coordinates");
    throw Error(ErrorCode::InvalidArgument, "tear: the blade (length " + text(shorter) +
                                                ") is over a million times shorter than its sweep (" +
                                                text(size) + "); check the end pose's coordinates");
  }
  if (glm::length(h1 - h0) + glm::length(t1 - t0) <= 1e-6 * size)
    throw Error(ErrorCode::InvalidArgument, "tear: the blade's start and end poses are identical");
  const glm::dvec3 n1 = glm::cross(t0 - h0, t1 - h0), n2 = glm::cross(t1 - h0, h1 - h0);
  glm::dvec3 n = n1 + n2;
  const double min_area2 = 1e-9 * size * size;
  if (glm::length(n) <= min_area2) n = glm::length(n1) >= glm::length(n2) ? n1 : n2;
  if (glm::length(n) <= min_area2)
    throw Error(ErrorCode::InvalidArgument,
                "tear: the blade moves along its own line; the swept quad has no area");
  const glm::dvec3 centre = 0.25 * (h0 + t0 + t1 + h1);
  const glm::dvec3 nn = glm::normalize(n);
  double off = 0.0;
  for (const auto& p : {h0, t0, t1, h1}) off = std::max(off, std::abs(glm::dot(p - centre, nn)));
  std::vector<Piece> pieces;
  if (off <= 1e-3 * size) {
    Piece p = make_piece(nn, centre);
    add_triangle(p, h0, t0, t1, min_area2);
    add_triangle(p, h0, t1, h1, min_area2);
    pieces.push_back(std::move(p));
  } else {
    for (const auto& tri : {std::array<glm::dvec3, 3>{h0, t0, t1}, std::array<glm::dvec3, 3>{h0, t1, h1}}) {
      const glm::dvec3 tn = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
      if (glm::length(tn) <= min_area2) continue;
      Piece p = make_piece(tn, (tri[0] + tri[1] + tri[2]) / 3.0);
      add_triangle(p, tri[0], tri[1], tri[2], min_area2);
      pieces.push_back(std::move(p));
    }
  }
  std::size_t tris = 0;
  for (const auto& p : pieces) tris += p.corners.size();
  if (tris == 0) throw Error(ErrorCode::InvalidArgument, "tear: the swept quad has no area");
  return pieces;
}

// Triangulates one face with points inserted in order along a straight chord: each point lands
// inside a sub-triangle (split in three) or on a sub-edge (its faces split in two). Inserted in
// chord order, consecutive chord points always end up joined by an edge.
class LocalTriangulation {
 public:
  LocalTriangulation(const Triangle& t) {
    points_ = {{t[0], {1, 0, 0}}, {t[1], {0, 1, 0}}, {t[2], {0, 0, 1}}};
    tris_ = {{0, 1, 2}};
  }
  /// Inserts a point; returns the vertex that represents it (itself, or a coincident vertex).
  VertexId insert(VertexId v, const glm::dvec3& bary) {
    const glm::dvec2 q(bary.y, bary.z);
    int best = -1;
    glm::dvec3 best_l(0.0);
    double best_min = -1e300;
    for (std::size_t i = 0; i < tris_.size(); ++i) {
      const glm::dvec3 l = local_bary(tris_[i], q);
      const double m = std::min({l.x, l.y, l.z});
      if (m > best_min) {
        best_min = m;
        best = static_cast<int>(i);
        best_l = l;
      }
    }
    constexpr double eps = 1e-9;
    int zeros = 0, zk = -1, nz = -1;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(best_l[k]) <= eps) {
        ++zeros;
        zk = k;
      } else {
        nz = k;
      }
    }
    const std::array<int, 3> t = tris_[best];
    if (zeros >= 2) return points_[t[nz]].v;  // coincides with an existing vertex
    const int id = static_cast<int>(points_.size());
    points_.push_back({v, bary});
    if (zeros == 0) {
      tris_[best] = {t[0], t[1], id};
      tris_.push_back({t[1], t[2], id});
      tris_.push_back({t[2], t[0], id});
      return v;
    }
    // On the edge opposite corner zk: split this triangle and the one across the edge.
    const int a = t[zk], b = t[(zk + 1) % 3], c = t[(zk + 2) % 3];
    tris_[best] = {a, b, id};
    tris_.push_back({a, id, c});
    for (std::size_t i = 0; i < tris_.size(); ++i) {
      auto& o = tris_[i];
      for (int k = 0; k < 3; ++k)
        if (o[k] == c && o[(k + 1) % 3] == b) {
          const int x = o[(k + 2) % 3];
          o = {x, c, id};
          tris_.push_back({x, id, b});
          return v;
        }
    }
    return v;
  }
  struct Point {
    VertexId v;
    glm::dvec3 bary;
  };
  const std::vector<Point>& points() const { return points_; }
  const std::vector<std::array<int, 3>>& triangles() const { return tris_; }

 private:
  glm::dvec3 local_bary(const std::array<int, 3>& t, const glm::dvec2& q) const {
    const glm::dvec2 a(points_[t[0]].bary.y, points_[t[0]].bary.z),
        b(points_[t[1]].bary.y, points_[t[1]].bary.z), c(points_[t[2]].bary.y, points_[t[2]].bary.z);
    const double d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (d == 0.0) return glm::dvec3(-1e300);
    const double l1 = ((q.x - a.x) * (c.y - a.y) - (q.y - a.y) * (c.x - a.x)) / d;
    const double l2 = ((b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x)) / d;
    return {1.0 - l1 - l2, l1, l2};
  }

  std::vector<Point> points_;
  std::vector<std::array<int, 3>> tris_;
};

class Tearer {
 public:
  Tearer(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const std::vector<glm::mat3>& skin_linear,
         const TearOptions& options, const TriangleGrid* index, const BoundingBox* posed_bounds)
      : mesh_(mesh),
        editor_(mesh),
        options_(options),
        input_posed_(posed),
        first_new_(static_cast<std::uint32_t>(mesh.vertex_count())),
        first_new_face_(static_cast<std::uint32_t>(mesh.face_slots())),
        index_(index),
        posed_bounds_(posed_bounds),
        input_linear_(skin_linear) {}

  TearResult run(const Blade& start, const Blade& end);

 private:
  struct Crossing {  // where the plane crosses a mesh edge
    VertexId lo, hi;
    double t;  // from lo to hi
    glm::dvec3 p;
    HValues h;
    bool in = false, split = false;
    VertexId v;
  };
  struct ZeroVertex {  // a vertex on the plane
    HValues h;
    bool in = false;
  };
  struct ChordEnd {
    glm::dvec3 p;
    glm::dvec3 bary;
    const HValues* h;
    VertexId corner;             // valid when the end is a face corner
    std::uint64_t crossing = 0;  // edge key otherwise
  };
  struct FacePlan {
    FaceId f;
    Triangle t;
    ChordEnd a, b;
    std::vector<Interval> torn;
    std::vector<double> interior;        // chord parameters of points strictly inside the face
    std::vector<VertexId> interior_ids;  // their vertices, once made
  };
  struct ZeroEdge {  // a mesh edge lying in the plane
    VertexId lo, hi;
    std::uint8_t sides = 0;  // bit 1: a face on the positive side, bit 2: negative
    int faces = 0;
    bool coplanar = false;
    std::vector<Interval> torn;
    std::vector<std::pair<double, VertexId>> points;  // split points (parameter from lo)
  };

  void tear_piece(const Piece& piece, std::size_t piece_index);
  void split_lone_edges();
  void separate_and_open(TearResult& result);
  const ZeroVertex& zero_vertex(const Piece& piece, VertexId v);
  Crossing& crossing(const Piece& piece, VertexId a, VertexId b);
  void add_torn(VertexId a, VertexId b, std::size_t piece);
  void note_new_vertex(VertexId v, const glm::dvec3& p, const VertexId* src, const double* w, int n);
  // Bind-to-world linear map of a vertex: the caller's, or the blend made for a new vertex.
  glm::mat3 linear(VertexId v) const {
    if (input_linear_.empty()) return glm::mat3(1.0f);
    if (v.index < input_linear_.size()) return input_linear_[v.index];
    auto it = new_linear_.find(v.index);
    return it == new_linear_.end() ? glm::mat3(1.0f) : it->second;
  }
  // Signed distance of `p` to the nearest of the listed pieces (its side of a folded quad).
  double nearest_side(const std::vector<std::size_t>& pieces, const glm::dvec3& p) const {
    double best = 1e300, side = 0.0;
    for (std::size_t i : pieces) {
      const Piece& pc = pieces_[i];
      const double d = glm::dot(p - pc.origin, pc.normal);
      const HValues h = hvalues(pc, pc.project(p));
      double out = 1e300;
      for (std::size_t j = 0; j < pc.corners.size(); ++j)
        out = std::min(out, std::max({0.0, -h[3 * j], -h[3 * j + 1], -h[3 * j + 2]}));
      const double dist = d * d + out * out;
      if (dist < best) {
        best = dist;
        side = d;
      }
    }
    return side;
  }

  SurfaceMesh& mesh_;
  MeshEditor editor_;
  TearOptions options_;
  // Posed positions: the caller's for existing vertices, ours for the ones the tear adds.
  const glm::vec3& posed(std::uint32_t v) const {
    return v < first_new_ ? input_posed_[v] : added_posed_[v - first_new_];
  }
  const std::vector<glm::vec3>& input_posed_;
  std::vector<glm::vec3> added_posed_;
  std::uint32_t first_new_;
  std::uint32_t first_new_face_;
  const TriangleGrid* index_;
  const BoundingBox* posed_bounds_;
  const std::vector<glm::mat3>& input_linear_;
  std::pmr::monotonic_buffer_resource arena_{std::size_t(1) << 16};  // before every map using it
  Map<std::uint32_t, glm::mat3> new_linear_{&arena_};  // vertices made by this tear
  std::vector<Piece> pieces_;
  double tol_ = 0.0;
  float width_ = 0.0f;
  // Per piece (cleared between pieces).
  // Signed distance to the piece's plane and its snapped sign, for the vertices of the faces
  // examined (the rest of the mesh is never visited).
  struct Classified {
    double dist;
    std::int8_t sign;
  };
  Map<std::uint32_t, Classified> classified_{&arena_};
  double dist(VertexId v) const {
    auto it = classified_.find(v.index);
    return it == classified_.end() ? 0.0 : it->second.dist;
  }
  std::int8_t sign(VertexId v) const {
    auto it = classified_.find(v.index);
    return it == classified_.end() ? 0 : it->second.sign;
  }
  Map<std::uint32_t, ZeroVertex> zero_{&arena_};
  Map<std::uint64_t, Crossing> crossings_{&arena_};
  // Over the whole tear.
  Map<std::uint64_t, std::size_t> torn_{&arena_};  // edge -> piece that tore it
  std::vector<FaceId> region_;                           // faces examined or made
  // Crossings that fell on one bind position (the two long edges of a needle split at the same
  // parameter): the later vertex maps to the earlier, so the needle's tip is not a zero-area face.
  Map<std::uint32_t, VertexId> merged_{&arena_};
  VertexId merged(VertexId v) const {
    for (auto it = merged_.find(v.index); it != merged_.end(); it = merged_.find(v.index)) v = it->second;
    return v;
  }
  std::size_t intersections_ = 0;
};

const Tearer::ZeroVertex& Tearer::zero_vertex(const Piece& piece, VertexId v) {
  auto it = zero_.find(v.index);
  if (it != zero_.end()) return it->second;
  ZeroVertex z{};
  z.h = hvalues(piece, piece.project(glm::dvec3(posed(v.index))));
  z.in = inside(piece, z.h);
  return zero_.emplace(v.index, z).first->second;
}

Tearer::Crossing& Tearer::crossing(const Piece& piece, VertexId a, VertexId b) {
  const auto key = edge_key(a, b);
  auto it = crossings_.find(key);
  if (it != crossings_.end()) return it->second;
  Crossing c;
  c.lo = a < b ? a : b;
  c.hi = a < b ? b : a;
  const double dl = dist(c.lo), dh = dist(c.hi);
  c.t = dl / (dl - dh);
  c.p = glm::mix(glm::dvec3(posed(c.lo.index)), glm::dvec3(posed(c.hi.index)), c.t);
  c.h = hvalues(piece, piece.project(c.p));
  c.in = inside(piece, c.h);
  c.split = c.in;
  return crossings_.emplace(key, c).first->second;
}

void Tearer::add_torn(VertexId a, VertexId b, std::size_t piece) {
  if (a == b) return;
  torn_.emplace(edge_key(a, b), piece);
}

void Tearer::note_new_vertex(VertexId v, const glm::dvec3& p, const VertexId* src, const double* w, int n) {
  if (added_posed_.size() <= v.index - first_new_) added_posed_.resize(v.index - first_new_ + 1);
  added_posed_[v.index - first_new_] = glm::vec3(p);
  if (!input_linear_.empty()) {
    glm::mat3 m(0.0f);
    for (int i = 0; i < n; ++i) m += float(w[i]) * linear(src[i]);
    new_linear_[v.index] = m;
  }
}

void Tearer::tear_piece(const Piece& piece, std::size_t piece_index) {
  classified_.clear();
  zero_.clear();
  crossings_.clear();

  // Faces whose posed bounding box meets the piece's (inflated by a few tolerances) and that
  // reach the band of the piece's plane (a face with every corner further than that on one side
  // has nothing to tear): from the index (plus the faces this tear made) when there is one, else
  // from a scan of every face.
  BoundingBox box = piece.box;
  const double band = 4.0 * tol_;
  const glm::vec3 pad(static_cast<float>(band));
  box.add(box.min - pad);
  box.add(box.max + pad);
  auto candidate = [&](const Triangle& t) {
    const glm::vec3 &a = posed(t[0].index), &b = posed(t[1].index), &c = posed(t[2].index);
    const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
    if (lo.x > box.max.x || lo.y > box.max.y || lo.z > box.max.z || hi.x < box.min.x || hi.y < box.min.y ||
        hi.z < box.min.z)
      return false;
    int above = 0, below = 0;
    for (const glm::vec3* p : {&a, &b, &c}) {
      const double d = glm::dot(glm::dvec3(*p) - piece.origin, piece.normal);
      above += d > band;
      below += d < -band;
    }
    return above < 3 && below < 3;
  };
  std::vector<FaceId> faces;
  if (index_) {
    const float reach = static_cast<float>(band) + 0.01f * index_->cell_size();
    for (FaceId f : index_->query_slab(box, glm::vec3(piece.origin), glm::vec3(piece.normal), reach))
      if (f.index < first_new_face_ && !mesh_.is_deleted(f) && candidate(mesh_.face(f))) faces.push_back(f);
    for (auto i = first_new_face_; i < mesh_.face_slots(); ++i)
      if (!mesh_.is_deleted(FaceId(i)) && candidate(mesh_.face(FaceId(i)))) faces.push_back(FaceId(i));
  } else {
    mesh_.for_each_face([&](FaceId f, const Triangle& t) {
      if (candidate(t)) faces.push_back(f);
    });
  }
  classified_.reserve(2 * faces.size() + 16);
  for (FaceId f : faces)
    for (auto v : mesh_.face(f)) {
      auto [it, inserted] = classified_.try_emplace(v.index, Classified{0.0, 0});
      if (!inserted) continue;
      const double d = glm::dot(glm::dvec3(posed(v.index)) - piece.origin, piece.normal);
      it->second = {d, static_cast<std::int8_t>(d > tol_ ? 1 : (d < -tol_ ? -1 : 0))};
    }

  // Plan: chords of faces crossed by the plane, clipped to the piece.
  std::vector<FacePlan> plans;
  Map<std::uint64_t, ZeroEdge> zero_edges(&arena_);
  for (FaceId f : faces) {
    const Triangle t = mesh_.face(f);
    const std::int8_t s[3] = {sign(t[0]), sign(t[1]), sign(t[2])};
    const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
    if (zeros == 3) {
      for (int k = 0; k < 3; ++k) {
        auto& ze = zero_edges[edge_key(t[k], t[(k + 1) % 3])];
        ze.lo = t[k] < t[(k + 1) % 3] ? t[k] : t[(k + 1) % 3];
        ze.hi = t[k] < t[(k + 1) % 3] ? t[(k + 1) % 3] : t[k];
        ze.coplanar = true;
        ++ze.faces;
      }
      continue;
    }
    if (zeros == 2) {
      int k = 0;
      while (s[(k + 2) % 3] == 0) ++k;  // the non-zero corner is k + 2
      const VertexId a = t[k], b = t[(k + 1) % 3];
      auto& ze = zero_edges[edge_key(a, b)];
      ze.lo = a < b ? a : b;
      ze.hi = a < b ? b : a;
      ze.sides |= s[(k + 2) % 3] > 0 ? 1 : 2;
      ++ze.faces;
      continue;
    }
    const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0, neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
    if (!pos || !neg) continue;  // no chord, or the plane only touches a corner
    FacePlan plan;
    plan.f = f;
    plan.t = t;
    ChordEnd ends[2];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      if (s[k] == 0) {
        const ZeroVertex& z = zero_vertex(piece, t[k]);
        glm::dvec3 bary(0.0);
        bary[k] = 1.0;
        ends[n++] = {glm::dvec3(posed(t[k].index)), bary, &z.h, t[k], 0};
      }
    }
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3;
      if (s[k] == 0 || s[k1] == 0 || s[k] == s[k1]) continue;
      Crossing& c = crossing(piece, t[k], t[k1]);
      glm::dvec3 bary(0.0);
      const double wk = t[k] == c.lo ? 1.0 - c.t : c.t;
      bary[k] = wk;
      bary[k1] = 1.0 - wk;
      ends[n++] = {c.p, bary, &c.h, VertexId(), edge_key(t[k], t[k1])};
    }
    if (n != 2) continue;
    plan.a = ends[0];
    plan.b = ends[1];
    const double len = glm::length(plan.b.p - plan.a.p);
    const double snap = len > 0.0 ? tol_ / len : 1.0;
    plan.torn = clip_segment(piece, *plan.a.h, *plan.b.h, snap);
    if (plan.torn.empty()) continue;
    for (const Interval& iv : plan.torn) {
      for (double s_end : {iv.lo, iv.hi}) {
        if (s_end == 0.0 && plan.a.crossing)
          crossings_.at(plan.a.crossing).split = true;
        else if (s_end == 1.0 && plan.b.crossing)
          crossings_.at(plan.b.crossing).split = true;
        else if (s_end > 0.0 && s_end < 1.0)
          plan.interior.push_back(s_end);
      }
    }
    std::sort(plan.interior.begin(), plan.interior.end());
    plans.push_back(std::move(plan));
  }
  // Edges lying in the plane tear where the surface passes through them (faces on both sides).
  bool any_edge_torn = false;
  for (auto& [key, ze] : zero_edges) {
    if (ze.coplanar || ze.faces != 2 || ze.sides != 3) continue;
    const ZeroVertex& za = zero_vertex(piece, ze.lo);
    const ZeroVertex& zb = zero_vertex(piece, ze.hi);
    const double len = glm::length(glm::dvec3(posed(ze.hi.index)) - glm::dvec3(posed(ze.lo.index)));
    ze.torn = clip_segment(piece, za.h, zb.h, len > 0.0 ? tol_ / len : 1.0);
    any_edge_torn |= !ze.torn.empty();
  }
  if (plans.empty() && !any_edge_torn) return;  // this piece tears nothing: leave the mesh as it is

  // Edits. New vertices: on crossed edges, on in-plane edges, inside faces.
  std::vector<std::uint64_t> split_keys;
  for (const auto& [key, c] : crossings_)
    if (c.split) split_keys.push_back(key);
  std::sort(split_keys.begin(), split_keys.end());  // deterministic vertex numbering
  for (std::uint64_t key : split_keys) {
    Crossing& c = crossings_.at(key);
    c.v = editor_.add_vertex_on_edge(c.lo, c.hi, static_cast<float>(c.t));
    const VertexId src[2] = {c.lo, c.hi};
    const double w[2] = {1.0 - c.t, c.t};
    note_new_vertex(c.v, c.p, src, w, 2);
    ++intersections_;
  }
  std::vector<std::uint64_t> zero_keys;
  for (const auto& [key, ze] : zero_edges)
    if (!ze.torn.empty()) zero_keys.push_back(key);
  std::sort(zero_keys.begin(), zero_keys.end());
  for (std::uint64_t key : zero_keys) {
    ZeroEdge& ze = zero_edges.at(key);
    std::vector<double> params;
    for (const Interval& iv : ze.torn)
      for (double s : {iv.lo, iv.hi})
        if (s > 0.0 && s < 1.0) params.push_back(s);
    std::sort(params.begin(), params.end());
    for (double s : params) {
      const VertexId v = editor_.add_vertex_on_edge(ze.lo, ze.hi, static_cast<float>(s));
      const VertexId src[2] = {ze.lo, ze.hi};
      const double w[2] = {1.0 - s, s};
      note_new_vertex(v, glm::mix(glm::dvec3(posed(ze.lo.index)), glm::dvec3(posed(ze.hi.index)), s), src,
                      w, 2);
      ze.points.emplace_back(s, v);
    }
  }
  for (FacePlan& plan : plans) {
    for (double s : plan.interior) {
      const glm::dvec3 bary = glm::mix(plan.a.bary, plan.b.bary, s);
      const VertexId v = editor_.add_vertex_in_triangle(plan.t, glm::vec3(bary));
      const double w[3] = {bary.x, bary.y, bary.z};
      note_new_vertex(v, glm::mix(plan.a.p, plan.b.p, s), plan.t.data(), w, 3);
      plan.interior_ids.push_back(v);
    }
  }

  // Re-triangulate every face that got a point: along its chord, in chord order. The sub-faces
  // are planned first and written after the merges below, which are checked against them.
  struct Insert {
    double s;
    VertexId v;
    glm::dvec3 bary;
  };
  struct Retriangulated {
    FaceId f;
    std::size_t plan;  // index into plans, or plans.size() for a face without a chord
    LocalTriangulation local;
    std::vector<std::pair<std::uint32_t, VertexId>> alias;  // inserted vertex -> coincident one
  };
  Map<std::uint32_t, std::size_t> plan_of(&arena_);
  for (std::size_t i = 0; i < plans.size(); ++i) plan_of.emplace(plans[i].f.index, i);
  std::vector<Retriangulated> retriangulated;
  for (FaceId f : faces) {
    const Triangle t = mesh_.face(f);
    std::vector<Insert> list;
    auto pit = plan_of.find(f.index);
    if (pit != plan_of.end()) {
      const FacePlan& plan = plans[pit->second];
      for (std::size_t i = 0; i < plan.interior.size(); ++i)
        list.push_back(
            {plan.interior[i], plan.interior_ids[i], glm::mix(plan.a.bary, plan.b.bary, plan.interior[i])});
    }
    // Points on this face's edges: split crossings and in-plane edge points. They all lie on the
    // face's chord (a crossing is a chord end of every face around its edge).
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3;
      const auto key = edge_key(t[k], t[k1]);
      auto cit = crossings_.find(key);
      if (cit != crossings_.end() && cit->second.split) {
        const Crossing& c = cit->second;
        glm::dvec3 bary(0.0);
        const double wk = t[k] == c.lo ? 1.0 - c.t : c.t;
        bary[k] = wk;
        bary[k1] = 1.0 - wk;
        double s = 0.0;
        if (pit != plan_of.end()) s = plans[pit->second].b.crossing == key ? 1.0 : 0.0;
        list.push_back({s, c.v, bary});
      }
      auto zit = zero_edges.find(key);
      if (zit != zero_edges.end() && !zit->second.points.empty()) {
        const ZeroEdge& ze = zit->second;
        for (const auto& [param, v] : ze.points) {
          glm::dvec3 bary(0.0);
          const double wk = t[k] == ze.lo ? 1.0 - param : param;
          bary[k] = wk;
          bary[k1] = 1.0 - wk;
          list.push_back({param, v, bary});
        }
      }
    }
    if (list.empty()) continue;
    std::sort(list.begin(), list.end(), [](const Insert& x, const Insert& y) { return x.s < y.s; });
    Retriangulated r{f, pit == plan_of.end() ? plans.size() : pit->second, LocalTriangulation(t), {}};
    for (const Insert& ins : list) {
      const VertexId got = r.local.insert(ins.v, ins.bary);
      if (got != ins.v) r.alias.emplace_back(ins.v.index, got);
    }
    retriangulated.push_back(std::move(r));
  }
  // The sub-faces as vertex triples (updated as crossings merge), and the ones at each vertex.
  std::vector<Triangle> planned;
  Map<std::uint32_t, std::vector<std::uint32_t>> planned_at(&arena_);
  for (const Retriangulated& r : retriangulated) {
    const auto& pts = r.local.points();
    for (const auto& tri : r.local.triangles()) {
      const Triangle nt = {pts[tri[0]].v, pts[tri[1]].v, pts[tri[2]].v};
      for (VertexId v : nt) planned_at[v.index].push_back(static_cast<std::uint32_t>(planned.size()));
      planned.push_back(nt);
    }
  }
  // Faces made twice (in either orientation) and directed edges used twice among the planned
  // faces `which`, with `from` renamed `to` (faces that become degenerate are not made).
  auto clashes = [&](const std::vector<std::uint32_t>& which, VertexId from, VertexId to) {
    std::vector<std::array<std::uint32_t, 3>> keys;
    std::vector<std::uint64_t> directed;
    for (std::uint32_t i : which) {
      Triangle t = planned[i];
      for (VertexId& v : t)
        if (v == from) v = to;
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      std::array<std::uint32_t, 3> k = {t[0].index, t[1].index, t[2].index};
      std::sort(k.begin(), k.end());
      keys.push_back(k);
      for (int j = 0; j < 3; ++j) directed.push_back((std::uint64_t(t[j].index) << 32) | t[(j + 1) % 3].index);
    }
    std::sort(keys.begin(), keys.end());
    std::sort(directed.begin(), directed.end());
    std::size_t n = 0;
    for (std::size_t i = 1; i < keys.size(); ++i) n += keys[i] == keys[i - 1];
    for (std::size_t i = 1; i < directed.size(); ++i) n += directed[i] == directed[i - 1];
    return n;
  };
  // Merging `hi` into `lo` may only drop the faces between them: every face it changes uses `lo`
  // afterwards, so the faces at the two vertices show any face it would make twice.
  auto merge_keeps_faces_apart = [&](VertexId hi, VertexId lo) {
    std::vector<std::uint32_t> which = planned_at[lo.index];
    const auto& at_hi = planned_at[hi.index];
    which.insert(which.end(), at_hi.begin(), at_hi.end());
    std::sort(which.begin(), which.end());
    which.erase(std::unique(which.begin(), which.end()), which.end());
    return clashes(which, hi, lo) <= clashes(which, hi, hi);
  };
  auto merge = [&](VertexId hi, VertexId lo) {
    merged_.emplace(hi.index, lo);
    auto it = planned_at.find(hi.index);
    if (it == planned_at.end()) return;
    for (std::uint32_t i : it->second) {
      for (VertexId& v : planned[i])
        if (v == hi) v = lo;
      planned_at[lo.index].push_back(i);
    }
    planned_at.erase(hi.index);
  };

  // A face whose lone corner has two long edges to corners a hair apart (a needle: the lips of a
  // narrow tear, a sliver) can have both crossings rounded to one bind position: they become one
  // vertex, and the needle's tip (a zero-area triangle) is not made. Same rule as the cut. The
  // tear also merges two crossings closer than its tolerance (posed) when the slit crosses the
  // face without stopping in it: left apart, they bound a sliver a few float steps wide, which
  // the opening (moving both along the blade's normal) would round to zero area. No merge may
  // make a face twice: around a spike's tip (a three-face cone whose every edge the slit crosses,
  // Fox seed 5 step 225) its other faces would become one triangle twice, reversed, and close
  // merges chained through a speck of faces a few tolerances across collapse its whole slit into
  // one vertex (SimpleSkin seed 11 step 177). Such a merge is refused.
  Set<std::uint32_t> stops(&arena_);  // faces the slit starts or ends in
  for (const FacePlan& plan : plans)
    if (!plan.interior.empty()) stops.insert(plan.f.index);
  for (FaceId f : faces) {
    const Triangle& t = mesh_.face(f);
    VertexId ends[3];
    glm::dvec3 at[3];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      auto cit = crossings_.find(edge_key(t[k], t[(k + 1) % 3]));
      if (cit != crossings_.end() && cit->second.split) {
        at[n] = cit->second.p;
        ends[n++] = merged(cit->second.v);
      }
    }
    if (n != 2 || ends[0] == ends[1]) continue;
    const VertexId lo = std::min(ends[0], ends[1]), hi = std::max(ends[0], ends[1]);
    if (mesh_.position(ends[0]) != mesh_.position(ends[1]) &&
        (glm::length(at[1] - at[0]) > tol_ || stops.count(f.index)))
      continue;
    if (merge_keeps_faces_apart(hi, lo)) merge(hi, lo);
  }
  for (std::uint64_t key : split_keys) {
    Crossing& c = crossings_.at(key);
    c.v = merged(c.v);
    // An edge torn by an earlier piece stays torn in its two halves.
    auto it = torn_.find(key);
    if (it != torn_.end()) {
      const std::size_t p = it->second;
      torn_.erase(it);
      add_torn(c.lo, c.v, p);
      add_torn(c.v, c.hi, p);
    }
  }
  for (std::uint64_t key : zero_keys) {
    ZeroEdge& ze = zero_edges.at(key);
    // An edge torn by an earlier piece stays torn in its pieces.
    auto it = torn_.find(key);
    if (it != torn_.end() && !ze.points.empty()) {
      const std::size_t p = it->second;
      torn_.erase(it);
      VertexId prev = ze.lo;
      for (const auto& [s, v] : ze.points) {
        add_torn(prev, v, p);
        prev = v;
      }
      add_torn(prev, ze.hi, p);
    }
  }

  for (const Retriangulated& r : retriangulated) {
    const FaceId f = r.f;
    editor_.remove_face(f);
    const auto& pts = r.local.points();
    for (const auto& tri : r.local.triangles()) {
      const Triangle nt = {merged(pts[tri[0]].v), merged(pts[tri[1]].v), merged(pts[tri[2]].v)};
      if (nt[0] == nt[1] || nt[1] == nt[2] || nt[0] == nt[2]) continue;  // a needle's tip whose crossings merged
      const FaceId nf = editor_.add_face_from(
          nt, f, {glm::vec3(pts[tri[0]].bary), glm::vec3(pts[tri[1]].bary), glm::vec3(pts[tri[2]].bary)});
      region_.push_back(nf);
    }
    // Torn pieces of this face's chord.
    if (r.plan < plans.size()) {
      const FacePlan& plan = plans[r.plan];
      std::vector<std::pair<double, VertexId>> chain;
      auto resolve = [&](VertexId v) {
        for (const auto& [from, to] : r.alias)
          if (from == v.index) return merged(to);
        return merged(v);
      };
      if (plan.a.corner.valid())
        chain.emplace_back(0.0, plan.a.corner);
      else if (crossings_.at(plan.a.crossing).split)
        chain.emplace_back(0.0, crossings_.at(plan.a.crossing).v);
      for (std::size_t i = 0; i < plan.interior.size(); ++i)
        chain.emplace_back(plan.interior[i], resolve(plan.interior_ids[i]));
      if (plan.b.corner.valid())
        chain.emplace_back(1.0, plan.b.corner);
      else if (crossings_.at(plan.b.crossing).split)
        chain.emplace_back(1.0, crossings_.at(plan.b.crossing).v);
      for (std::size_t i = 0; i + 1 < chain.size(); ++i)
        if (in_intervals(plan.torn, 0.5 * (chain[i].first + chain[i + 1].first)))
          add_torn(chain[i].second, chain[i + 1].second, piece_index);
    }
  }
  for (FaceId f : faces) region_.push_back(f);
  for (std::uint64_t key : zero_keys) {
    const ZeroEdge& ze = zero_edges.at(key);
    std::vector<std::pair<double, VertexId>> chain = {{0.0, ze.lo}};
    chain.insert(chain.end(), ze.points.begin(), ze.points.end());
    chain.emplace_back(1.0, ze.hi);
    for (std::size_t i = 0; i + 1 < chain.size(); ++i)
      if (in_intervals(ze.torn, 0.5 * (chain[i].first + chain[i + 1].first)))
        add_torn(chain[i].second, chain[i + 1].second, piece_index);
  }
}

// A slit made of one torn edge between two ends (a blade path inside one face, or across one
// corner) has no interior vertex to duplicate: give it one at the edge's midpoint.
void Tearer::split_lone_edges() {
  Map<std::uint32_t, int> degree(&arena_);
  for (const auto& [key, piece] : torn_) {
    ++degree[static_cast<std::uint32_t>(key >> 32)];
    ++degree[static_cast<std::uint32_t>(key & 0xffffffffu)];
  }
  std::vector<std::uint64_t> lone;
  for (const auto& [key, piece] : torn_)
    if (degree[static_cast<std::uint32_t>(key >> 32)] == 1 &&
        degree[static_cast<std::uint32_t>(key & 0xffffffffu)] == 1)
      lone.push_back(key);
  if (lone.empty()) return;
  std::sort(lone.begin(), lone.end());
  Map<std::uint64_t, std::vector<FaceId>> faces_of(&arena_);
  for (std::uint64_t key : lone) faces_of[key];
  std::sort(region_.begin(), region_.end());
  region_.erase(std::unique(region_.begin(), region_.end()), region_.end());
  for (FaceId f : region_) {
    if (mesh_.is_deleted(f)) continue;
    const Triangle& t = mesh_.face(f);
    for (int k = 0; k < 3; ++k) {
      auto it = faces_of.find(edge_key(t[k], t[(k + 1) % 3]));
      if (it != faces_of.end()) it->second.push_back(f);
    }
  }
  for (std::uint64_t key : lone) {
    const VertexId a(static_cast<std::uint32_t>(key >> 32)), b(static_cast<std::uint32_t>(key & 0xffffffffu));
    const std::size_t piece = torn_.at(key);
    const VertexId m = editor_.add_vertex_on_edge(a, b, 0.5f);
    const VertexId src[2] = {a, b};
    const double w[2] = {0.5, 0.5};
    note_new_vertex(m, 0.5 * (glm::dvec3(posed(a.index)) + glm::dvec3(posed(b.index))), src, w, 2);
    for (FaceId f : faces_of[key]) {
      const Triangle t = mesh_.face(f);
      int k = 0;
      while (edge_key(t[k], t[(k + 1) % 3]) != key) ++k;
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      glm::vec3 ek(0.0f), ek1(0.0f), ek2(0.0f), mid(0.0f);
      ek[k] = 1.0f;
      ek1[k1] = 1.0f;
      ek2[k2] = 1.0f;
      mid[k] = 0.5f;
      mid[k1] = 0.5f;
      editor_.remove_face(f);
      region_.push_back(editor_.add_face_from({t[k], m, t[k2]}, f, {ek, mid, ek2}));
      region_.push_back(editor_.add_face_from({m, t[k1], t[k2]}, f, {mid, ek1, ek2}));
    }
    torn_.erase(key);
    add_torn(a, m, piece);
    add_torn(m, b, piece);
  }
}

// Splits the vertices along the torn edges into one copy per wedge of faces between torn edges,
// then pushes the lips apart.
void Tearer::separate_and_open(TearResult& result) {
  // Chain vertices and their torn degree.
  Map<std::uint32_t, std::vector<std::uint32_t>> graph(&arena_);
  for (const auto& [key, piece] : torn_) {
    const auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xffffffffu);
    graph[a].push_back(b);
    graph[b].push_back(a);
  }
  std::vector<std::uint32_t> chain;
  for (const auto& [v, nb] : graph) chain.push_back(v);
  std::sort(chain.begin(), chain.end());
  for (auto& [v, nb] : graph) std::sort(nb.begin(), nb.end());

  // Stars of the chain vertices (every face around a chain vertex is in the region).
  std::sort(region_.begin(), region_.end());
  region_.erase(std::unique(region_.begin(), region_.end()), region_.end());
  Map<std::uint32_t, std::vector<FaceId>> star(&arena_);
  for (FaceId f : region_) {
    if (mesh_.is_deleted(f)) continue;
    for (auto v : mesh_.face(f))
      if (graph.count(v.index)) star[v.index].push_back(f);
  }

  // Wedges: faces around v connected across edges (v, x) that are not torn.
  struct Wedge {
    std::vector<FaceId> faces;
  };
  Map<std::uint32_t, std::vector<Wedge>> wedges(&arena_);
  Set<std::uint32_t> on_boundary(&arena_);  // chain vertices on a boundary before this tear
  for (std::uint32_t v : chain) {
    const auto& fs = star[v];
    std::vector<std::uint32_t> parent(fs.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    // (neighbour, face) pairs, grouped by neighbour with the faces in star order.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> around;
    around.reserve(2 * fs.size());
    for (std::uint32_t i = 0; i < fs.size(); ++i) {
      const Triangle& t = mesh_.face(fs[i]);
      for (int k = 0; k < 3; ++k)
        if (t[k].index == v) {
          around.emplace_back(t[(k + 1) % 3].index, i);
          around.emplace_back(t[(k + 2) % 3].index, i);
        }
    }
    std::stable_sort(around.begin(), around.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t n_around = around.size();
    for (std::size_t lo = 0, hi = 0; lo < n_around; lo = hi) {
      const std::uint32_t x = around[lo].first;
      hi = lo + 1;
      while (hi < n_around && around[hi].first == x) ++hi;
      const bool torn = torn_.count(edge_key(VertexId(v), VertexId(x))) != 0;
      if (hi - lo == 1 && !torn) on_boundary.insert(v);
      if (torn) continue;
      for (std::size_t i = lo + 1; i < hi; ++i) {
        const auto a = root(around[lo].second), b = root(around[i].second);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    // A set's root is its smallest member, so groups in order of first member are groups in
    // order of root.
    auto& list = wedges[v];
    std::vector<std::uint32_t> group_of(fs.size(), kInvalidIndex);
    for (std::uint32_t i = 0; i < fs.size(); ++i) {
      const std::uint32_t r = root(i);
      if (group_of[r] == kInvalidIndex) {
        group_of[r] = static_cast<std::uint32_t>(list.size());
        list.emplace_back();
      }
      list[group_of[r]].faces.push_back(fs[i]);
    }
  }

  // Taper along each slit: arc length to the nearest end (torn degree 1, or an old boundary).
  Map<std::uint32_t, double> to_end(&arena_);
  Map<std::uint32_t, std::uint32_t> comp(&arena_);
  std::vector<double> comp_length;
  std::vector<bool> comp_has_end;
  auto edge_len = [&](std::uint32_t a, std::uint32_t b) {
    return static_cast<double>(glm::length(posed(a) - posed(b)));
  };
  for (std::uint32_t v : chain) {
    if (comp.count(v)) continue;
    const auto c = static_cast<std::uint32_t>(comp_length.size());
    comp_length.push_back(0.0);
    comp_has_end.push_back(false);
    std::vector<std::uint32_t> stack = {v}, members;
    comp[v] = c;
    while (!stack.empty()) {
      const auto x = stack.back();
      stack.pop_back();
      members.push_back(x);
      for (auto y : graph[x]) {
        if (x < y) comp_length[c] += edge_len(x, y);
        if (!comp.count(y)) {
          comp[y] = c;
          stack.push_back(y);
        }
      }
    }
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (auto x : members) {
      if (graph[x].size() == 1 || on_boundary.count(x)) {
        to_end[x] = 0.0;
        queue.emplace(0.0, x);
        comp_has_end[c] = true;
      }
    }
    while (!queue.empty()) {
      const auto [d, x] = queue.top();
      queue.pop();
      if (d > to_end[x]) continue;
      for (auto y : graph[x]) {
        const double nd = d + edge_len(x, y);
        auto it = to_end.find(y);
        if (it == to_end.end() || nd < it->second) {
          to_end[y] = nd;
          queue.emplace(nd, y);
        }
      }
    }
  }
  result.slits = comp_length.size();
  for (bool has_end : comp_has_end) result.closed_slits += has_end ? 0 : 1;

  // Lip normal at each chain vertex: the normal of the piece(s) that tore its edges.
  Map<std::uint32_t, glm::dvec3> lip_normal(&arena_);
  Map<std::uint32_t, std::vector<std::size_t>> vertex_pieces(&arena_);
  for (const auto& [key, piece] : torn_) {
    for (const auto v :
         {static_cast<std::uint32_t>(key >> 32), static_cast<std::uint32_t>(key & 0xffffffffu)}) {
      auto& list = vertex_pieces[v];
      if (std::find(list.begin(), list.end(), piece) == list.end()) {
        list.push_back(piece);
        lip_normal[v] += pieces_[piece].normal;
      }
    }
  }

  // Split: wedge 0 keeps the vertex, every other wedge gets a copy.
  struct Lip {
    VertexId v;        // vertex or copy
    std::uint32_t of;  // chain vertex it came from
    std::vector<FaceId> faces;
    glm::dvec3 move{0.0};  // world displacement
  };
  std::vector<Lip> lips;
  Map<std::uint32_t, std::vector<std::pair<std::uint32_t, VertexId>>> replace(&arena_);  // face -> (old, new)
  std::vector<VertexId> tear_vertices;
  Set<std::uint32_t> split_from(&arena_);  // copies made here
  for (std::uint32_t v : chain) {
    auto& ws = wedges[v];
    tear_vertices.push_back(VertexId(v));
    if (ws.size() < 2) continue;
    for (std::size_t w = 0; w < ws.size(); ++w) {
      VertexId id(v);
      if (w > 0) {
        id = editor_.split_vertex(VertexId(v));
        const VertexId src[1] = {VertexId(v)};
        const double one[1] = {1.0};
        note_new_vertex(id, glm::dvec3(posed(v)), src, one, 1);
        tear_vertices.push_back(id);
        split_from.insert(id.index);
        for (FaceId f : ws[w].faces) replace[f.index].emplace_back(v, id);
      }
      lips.push_back({id, v, ws[w].faces, glm::dvec3(0.0)});
    }
  }
  Map<std::uint32_t, FaceId> renamed(&arena_);
  std::vector<std::uint32_t> replaced_faces;
  for (const auto& [f, list] : replace) replaced_faces.push_back(f);
  std::sort(replaced_faces.begin(), replaced_faces.end());
  const glm::vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (std::uint32_t fi : replaced_faces) {
    Triangle t = mesh_.face(FaceId(fi));
    for (const auto& [old, copy] : replace[fi])
      for (auto& v : t)
        if (v.index == old) v = copy;
    editor_.remove_face(FaceId(fi));
    renamed.emplace(fi, editor_.add_face_from(t, FaceId(fi), {e[0], e[1], e[2]}));
  }
  for (Lip& lip : lips)
    for (FaceId& f : lip.faces) {
      auto it = renamed.find(f.index);
      if (it != renamed.end()) f = it->second;
    }
  std::sort(tear_vertices.begin(), tear_vertices.end());
  result.tear_vertices = tear_vertices;

  // Opening: each lip moves half the width, tapered, away from the plane on its own side.
  if (width_ > 0.0f) {
    Map<std::uint32_t, std::size_t> lip_of(&arena_);  // vertex -> lip
    for (std::size_t i = 0; i < lips.size(); ++i) {
      Lip& lip = lips[i];
      const std::uint32_t c = comp[lip.of];
      const double length = comp_length[c];
      double taper = 1.0;
      if (comp_has_end[c] && length > 0.0) {
        auto it = to_end.find(lip.of);
        const double d = it == to_end.end() ? 0.5 * length : std::min(it->second, 0.5 * length);
        taper = std::sin(kPi * d / length);
      }
      glm::dvec3 n = lip_normal[lip.of];
      if (glm::length(n) == 0.0 || taper <= 0.0) continue;
      n = glm::normalize(n);
      // Which side the wedge lies on: its vertices off the tear, measured against the plane(s)
      // of the piece(s) that tore this vertex (the centroids would mislead at a folded quad's
      // crease, where the other piece's lip vertices stand off the mean plane).
      double side = 0.0, fallback = 0.0;
      const glm::dvec3 pv(posed(lip.of));
      const auto& planes = vertex_pieces[lip.of];
      for (FaceId f : lip.faces) {
        const Triangle& t = mesh_.face(f);
        glm::dvec3 centre(0.0);
        for (auto x : t) {
          const glm::dvec3 px(posed(x.index));
          centre += px / 3.0;
          if (graph.count(x.index) || split_from.count(x.index)) continue;
          side += nearest_side(planes, px);
        }
        fallback += glm::dot(centre - pv, n);
      }
      if (side == 0.0) side = fallback;
      if (side == 0.0) continue;
      // No lip moves further than the longest edge of its faces: a longer move flips them anyway,
      // and halving from a huge width (1e9) would give up before reaching a size that fits.
      double reach = 0.0;
      for (FaceId f : lip.faces) {
        const Triangle& t = mesh_.face(f);
        for (int k = 0; k < 3; ++k)
          reach = std::max(reach, glm::length(glm::dvec3(posed(t[k].index)) - glm::dvec3(posed(t[(k + 1) % 3].index))));
      }
      const double half = std::min(0.5 * double(width_) * taper, reach);
      lip.move = (side > 0.0 ? 1.0 : -1.0) * half * n;
      lip_of.emplace(lip.v.index, i);
    }
    // Halve moves that would flip a face (or nearly collapse it), until none does.
    std::vector<FaceId> check;
    for (const Lip& lip : lips)
      if (glm::length(lip.move) > 0.0) check.insert(check.end(), lip.faces.begin(), lip.faces.end());
    std::sort(check.begin(), check.end());
    check.erase(std::unique(check.begin(), check.end()), check.end());
    // Each face's corners and lips are looked up once. A face is evaluated again only when one
    // of its lips changed since its last evaluation (at or after it, in face order): otherwise it
    // would pass again, so the rounds give what evaluating every face every round gives.
    struct Check {
      glm::dvec3 p[3];
      glm::dvec3 n0;
      double l0;
      std::uint32_t lip[3];
      std::uint64_t evaluated = 0;  // clock of the last evaluation (0: never)
    };
    std::vector<Check> checks;
    checks.reserve(check.size());
    for (FaceId f : check) {
      const Triangle& t = mesh_.face(f);
      Check c;
      for (int k = 0; k < 3; ++k) {
        c.p[k] = glm::dvec3(posed(t[k].index));
        auto it = lip_of.find(t[k].index);
        c.lip[k] = it == lip_of.end() ? kInvalidIndex : static_cast<std::uint32_t>(it->second);
      }
      c.n0 = glm::cross(c.p[1] - c.p[0], c.p[2] - c.p[0]);
      c.l0 = glm::length(c.n0);
      if (c.l0 == 0.0) continue;  // never flips, never halves
      checks.push_back(c);
    }
    std::vector<std::uint64_t> changed(lips.size(), 0);  // clock of each lip's last halving
    std::uint64_t clock = 0;
    for (int round = 0; round < 12; ++round) {
      bool flipped = false;
      for (Check& c : checks) {
        if (c.evaluated != 0) {
          bool dirty = false;
          for (std::uint32_t l : c.lip) dirty |= l != kInvalidIndex && changed[l] >= c.evaluated;
          if (!dirty) continue;
        }
        c.evaluated = ++clock;
        glm::dvec3 m[3];
        for (int k = 0; k < 3; ++k) m[k] = c.lip[k] == kInvalidIndex ? c.p[k] : c.p[k] + lips[c.lip[k]].move;
        const glm::dvec3 n1 = glm::cross(m[1] - m[0], m[2] - m[0]);
        if (glm::dot(c.n0, n1) > 0.25 * c.l0 * glm::length(n1) && glm::length(n1) > 0.2 * c.l0) continue;
        flipped = true;
        for (std::uint32_t l : c.lip)
          if (l != kInvalidIndex) {
            lips[l].move *= round == 11 ? 0.0 : 0.5;
            changed[l] = clock;
          }
      }
      if (!flipped) break;
    }
    // Bind positions after the opening, as stored (float). Two lip vertices a few float steps
    // apart (the crossings of a needle, a sliver's corners) moved together can round onto one
    // point, which the check above (posed, in double) cannot see: a face that would lose its
    // area keeps its lips where they were, until no face does.
    std::vector<glm::vec3> target(lips.size());
    std::vector<bool> moving(lips.size(), false);
    for (std::size_t i = 0; i < lips.size(); ++i) {
      if (glm::length(lips[i].move) == 0.0) continue;
      const glm::mat3 m = linear(lips[i].v);
      if (std::abs(glm::determinant(m)) < 1e-12f) continue;
      target[i] = mesh_.position(lips[i].v) + glm::inverse(m) * glm::vec3(lips[i].move);
      moving[i] = true;
    }
    auto has_area = [](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
      const glm::dvec3 x(a), y(b), z(c);
      return glm::length(glm::cross(y - x, z - x)) > 0.0;
    };
    for (bool again = true; again;) {
      again = false;
      for (FaceId f : check) {
        const Triangle& t = mesh_.face(f);
        glm::vec3 p[3];
        bool moved = false;
        std::uint32_t lip[3];
        for (int k = 0; k < 3; ++k) {
          auto it = lip_of.find(t[k].index);
          lip[k] = it == lip_of.end() ? kInvalidIndex : static_cast<std::uint32_t>(it->second);
          moved |= lip[k] != kInvalidIndex && moving[lip[k]];
          p[k] = lip[k] != kInvalidIndex && moving[lip[k]] ? target[lip[k]] : mesh_.position(t[k]);
        }
        if (!moved || has_area(p[0], p[1], p[2]) ||
            !has_area(mesh_.position(t[0]), mesh_.position(t[1]), mesh_.position(t[2])))
          continue;
        for (std::uint32_t l : lip)
          if (l != kInvalidIndex) moving[l] = false;
        again = true;
      }
    }
    for (std::size_t i = 0; i < lips.size(); ++i)
      if (!moving[i]) lips[i].move = glm::dvec3(0.0);
    // The opening achieved: the widest gap between two copies of one slit vertex.
    Map<std::uint32_t, std::vector<glm::dvec3>> moves_of(&arena_);
    for (const Lip& lip : lips) moves_of[lip.of].push_back(lip.move);
    double opening = 0.0;
    for (const auto& [of, moves] : moves_of)
      for (std::size_t i = 0; i < moves.size(); ++i)
        for (std::size_t j = i + 1; j < moves.size(); ++j) opening = std::max(opening, glm::length(moves[i] - moves[j]));
    result.opening = static_cast<float>(opening);
    for (std::size_t i = 0; i < lips.size(); ++i)
      if (moving[i]) editor_.move_vertex(lips[i].v, target[i]);
  }
}

TearResult Tearer::run(const Blade& start, const Blade& end) {
  TearResult result;
  const std::size_t nv = mesh_.vertex_count();
  if (input_posed_.size() != nv)
    throw Error(ErrorCode::InvalidArgument, "tear: " + std::to_string(input_posed_.size()) +
                                                " posed positions for " + std::to_string(nv) + " vertices");
  if (!input_linear_.empty() && input_linear_.size() != nv)
    throw Error(ErrorCode::InvalidArgument, "tear: " + std::to_string(input_linear_.size()) +
                                                " skin matrices for " + std::to_string(nv) + " vertices");
  if (!std::isfinite(options_.width))
    throw Error(ErrorCode::InvalidArgument, "tear: the width is not finite");
  if (!(options_.relative_tolerance >= 0.0f) || !std::isfinite(options_.relative_tolerance))
    throw Error(ErrorCode::InvalidArgument, "tear: the tolerance must be a finite number >= 0");
  pieces_ = make_pieces(start, end);
  width_ = resolved_tear_width(start, end, options_);
  result.width = width_;
  // The model size: the bounds given, the index's, or those of every posed position.
  BoundingBox box;
  if (posed_bounds_) {
    box = *posed_bounds_;
  } else if (index_ && !index_->empty()) {
    box = index_->bounds();
  } else {
    box = parallel_reduce(
        input_posed_.size(), 65536, BoundingBox(),
        [&](std::size_t b, std::size_t e) {
          BoundingBox part;
          for (std::size_t i = b; i < e; ++i) part.add(input_posed_[i]);
          return part;
        },
        [](BoundingBox acc, const BoundingBox& part) {
          acc.add(part);
          return acc;
        });
  }
  tol_ = double(options_.relative_tolerance) * double(box.diagonal());
  for (std::size_t i = 0; i < pieces_.size(); ++i) tear_piece(pieces_[i], i);
  if (torn_.empty() && editor_.log().empty()) {
    result.status = OpStatus::NoIntersection;
    return result;
  }
  split_lone_edges();
  separate_and_open(result);
  // Lips are split per wedge of untorn edges; a vertex the tear touched elsewhere (a slit end on
  // an old boundary, a face replaced around a vertex on the quad) can still join two fans.
  const auto touched = detail::edited_vertices(editor_.log());
  const auto pinches = detail::split_pinched_vertices(
      editor_, touched, detail::faces_around(mesh_, editor_.log(), touched, first_new_, index_, input_posed_));
  for (const auto& [v, c] : pinches.copies)
    if (std::binary_search(result.tear_vertices.begin(), result.tear_vertices.end(), v)) result.tear_vertices.push_back(c);
  std::sort(result.tear_vertices.begin(), result.tear_vertices.end());
  result.intersection_points = intersections_;
  result.log = editor_.take_log();
  return result;
}

}  // namespace

std::vector<std::array<glm::vec3, 3>> swept_quad_triangles(const Blade& start, const Blade& end) {
  std::vector<std::array<glm::vec3, 3>> out;
  for (const Piece& p : make_pieces(start, end)) out.insert(out.end(), p.world.begin(), p.world.end());
  return out;
}

float resolved_tear_width(const Blade& start, const Blade& end, const TearOptions& options) {
  if (options.width >= 0.0f) return options.width;
  return 0.05f * 0.5f * (glm::length(start.tip - start.handle) + glm::length(end.tip - end.handle));
}

TearResult tear_mesh(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed,
                     const std::vector<glm::mat3>& skin_linear, const Blade& start, const Blade& end,
                     const TearOptions& options, const TriangleGrid* index, const BoundingBox* posed_bounds) {
  return Tearer(mesh, posed, skin_linear, options, index, posed_bounds).run(start, end);
}

namespace {

// World positions and the linear part of the bind-to-world map of every vertex of one instance.
void instance_pose(const Model& model, int node, const SurfaceMesh& mesh, const std::vector<glm::mat4>& world,
                   std::vector<glm::vec3>& posed, std::vector<glm::mat3>& linear) {
  const Node& n = model.nodes.at(static_cast<std::size_t>(node));
  const auto& p = mesh.positions();
  posed.resize(p.size());
  linear.resize(p.size());
  constexpr std::size_t kGrain = 16384;
  std::vector<glm::mat4> joints;
  if (n.skin >= 0 && static_cast<std::size_t>(n.skin) < model.skins.size())
    joints = joint_matrices(model, n.skin, world);
  const SkinBlend blend(mesh, joints);
  if (!blend.skinned()) {
    const glm::mat4& m = world.at(static_cast<std::size_t>(node));
    parallel_for(p.size(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v < e; ++v) {
        posed[v] = glm::vec3(m * glm::vec4(p[v], 1.0f));
        linear[v] = glm::mat3(m);
      }
    });
    return;
  }
  parallel_for(p.size(), kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const glm::mat4 m = blend.matrix(v);
      posed[v] = glm::vec3(m * glm::vec4(p[v], 1.0f));
      linear[v] = glm::mat3(m);
    }
  });
}

}  // namespace

ModelTearResult tear_model(Model& model, const Blade& start, const Blade& end, const TearOptions& options,
                           int animation, float time, PosedModel* index) {
  make_pieces(start, end);  // reject a degenerate blade even when the model has no mesh
  const Pose pose = sample_pose(model, animation, time);
  const auto world = world_matrices(model, pose);
  if (index) index->prepare(model, animation, time);
  ModelTearResult result;
  result.status = OpStatus::NoIntersection;
  result.width = resolved_tear_width(start, end, options);
  std::vector<int> mesh_users(model.meshes.size(), 0);
  for (const auto& n : model.nodes)
    if (n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < model.meshes.size()) ++mesh_users[n.mesh];
  std::vector<glm::vec3> own_posed;
  std::vector<glm::mat3> own_linear;
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    const int node_id = static_cast<int>(ni);
    // A mesh drawn by several instances is torn on a copy that this instance then owns.
    const bool shared = mesh_users[mi] > 1;
    Mesh copy;
    Mesh& target = shared ? (copy = model.meshes[mi], copy) : model.meshes[mi];
    bool any = false;
    for (std::size_t pi = 0; pi < target.primitives.size(); ++pi) {
      Primitive& prim = target.primitives[pi];
      PosedMesh* inst = index ? index->find(node_id, static_cast<int>(pi)) : nullptr;
      if (!inst) instance_pose(model, node_id, prim.mesh, world, own_posed, own_linear);
      // With the index, its exact bounds of the posed positions are the model size the tear
      // measures without one, so both give the same slits.
      const TearResult r = inst ? tear_mesh(prim.mesh, inst->posed, inst->linear, start, end, options, &inst->grid,
                                            &inst->bounds)
                                : tear_mesh(prim.mesh, own_posed, own_linear, start, end, options);
      if (r.status != OpStatus::Ok) continue;
      if (inst) index->follow(model, node_id, static_cast<int>(pi), prim.mesh, r.log);
      any = true;
      result.intersection_points += r.intersection_points;
      result.tear_vertices += r.tear_vertices.size();
      result.slits += r.slits;
      result.opening = std::max(result.opening, r.opening);
    }
    if (!any) continue;
    result.status = OpStatus::Ok;
    if (shared) {
      --mesh_users[mi];
      model.meshes.push_back(std::move(copy));
      model.nodes[ni].mesh = static_cast<int>(model.meshes.size() - 1);
      mesh_users.push_back(1);
      if (index) index->rename_mesh(node_id, model.nodes[ni].mesh);
    }
  }
  return result;
}

}  // namespace deepcut
