// SPDX-License-Identifier: MIT
#include "deepcut/core/ops/tear.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

using Tri3 = std::array<glm::vec3, 3>;

// tear_mesh on a mesh on its own, at rest.
TearResult tear_at_rest(SurfaceMesh& mesh, const Blade& start, const Blade& end, const TearOptions& options = {}) {
  PosedMesh posed = PosedMesh::at_positions(mesh);
  return tear_mesh(mesh, posed, start, end, options);
}

// Closest distance from p to a triangle (3D).
double point_triangle_distance(const glm::dvec3& p, const Tri3& t) {
  const glm::dvec3 a(t[0]), b(t[1]), c(t[2]);
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  const glm::dvec3 q = p - glm::dot(p - a, n) * n;
  const glm::dvec3 e[3] = {b - a, c - b, a - c}, o[3] = {a, b, c};
  bool in = true;
  for (int k = 0; k < 3; ++k) in &= glm::dot(glm::cross(e[k], q - o[k]), n) >= 0.0;
  if (in) return std::abs(glm::dot(p - a, n));
  double best = 1e300;
  for (int k = 0; k < 3; ++k) {
    const double s = std::clamp(glm::dot(p - o[k], e[k]) / glm::dot(e[k], e[k]), 0.0, 1.0);
    best = std::min(best, glm::length(p - (o[k] + s * e[k])));
  }
  return best;
}

double quad_distance(const glm::vec3& p, const std::vector<Tri3>& quad) {
  double best = 1e300;
  for (const auto& t : quad) best = std::min(best, point_triangle_distance(glm::dvec3(p), t));
  return best;
}

// Whether segment p-q crosses the interior of one of the quad's triangles (by more than `margin`
// from the triangle's edges, with both ends more than `margin` off its plane).
bool crosses_quad(const glm::vec3& p, const glm::vec3& q, const std::vector<Tri3>& quad, double margin) {
  for (const auto& t : quad) {
    const glm::dvec3 a(t[0]), b(t[1]), c(t[2]);
    const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
    const double dp = glm::dot(glm::dvec3(p) - a, n), dq = glm::dot(glm::dvec3(q) - a, n);
    if (!((dp > margin && dq < -margin) || (dp < -margin && dq > margin))) continue;
    const glm::dvec3 x = glm::dvec3(p) + (dp / (dp - dq)) * (glm::dvec3(q) - glm::dvec3(p));
    const glm::dvec3 e[3] = {b - a, c - b, a - c}, o[3] = {a, b, c};
    bool in = true;
    for (int k = 0; k < 3; ++k) in &= glm::dot(glm::cross(glm::normalize(e[k]), x - o[k]), n) > margin;
    if (in) return true;
  }
  return false;
}

// Boundary loops of a mesh: boundary half-edges chained into cycles. Returns the loops' vertex
// lists; `open_chains` counts chains that do not close (there should be none).
std::vector<std::vector<std::uint32_t>> boundary_loops(const SurfaceMesh& mesh,
                                                       std::size_t* open_chains = nullptr) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k].index, t[(k + 1) % 3].index}];
  });
  std::multimap<std::uint32_t, std::uint32_t> next;
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first})) next.emplace(e.first, e.second);
  std::vector<std::vector<std::uint32_t>> loops;
  std::size_t open = 0;
  while (!next.empty()) {
    auto it = next.begin();
    const std::uint32_t first = it->first;
    std::vector<std::uint32_t> loop = {first};
    std::uint32_t cur = it->second;
    next.erase(it);
    while (cur != first) {
      loop.push_back(cur);
      auto n = next.find(cur);
      if (n == next.end()) {
        ++open;
        break;
      }
      cur = n->second;
      next.erase(n);
    }
    loops.push_back(loop);
  }
  if (open_chains) *open_chains = open;
  return loops;
}

// Root input face of every face slot, following the log's FaceAdded parents.
std::vector<std::uint32_t> face_roots(const SurfaceMesh& mesh, std::size_t input_faces, const EditLog& log) {
  std::vector<std::uint32_t> root(mesh.face_slots());
  for (std::uint32_t f = 0; f < root.size(); ++f) root[f] = f;
  for (const Edit& e : log.edits)
    if (const auto* a = std::get_if<FaceAdded>(&e))
      if (a->parent.valid())
        root[a->f.index] = a->parent.index < input_faces ? a->parent.index : root[a->parent.index];
  return root;
}

glm::dvec3 face_normal(const SurfaceMesh& mesh, const Triangle& t) {
  const glm::dvec3 a(mesh.position(t[0])), b(mesh.position(t[1])), c(mesh.position(t[2]));
  return glm::cross(b - a, c - a);
}

// A random blade sweep through a random surface point of `mesh` (bind pose).
std::pair<Blade, Blade> random_sweep(const SurfaceMesh& mesh, std::mt19937& rng, bool twisted) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::vector<FaceId> faces;
  mesh.for_each_face([&](FaceId f, const Triangle&) { faces.push_back(f); });
  const Triangle& t = mesh.face(faces[std::uniform_int_distribution<std::size_t>(0, faces.size() - 1)(rng)]);
  float b1 = u01(rng), b2 = u01(rng);
  if (b1 + b2 > 1.0f) {
    b1 = 1.0f - b1;
    b2 = 1.0f - b2;
  }
  const glm::vec3 c =
      mesh.position(t[0]) * (1.0f - b1 - b2) + mesh.position(t[1]) * b1 + mesh.position(t[2]) * b2;
  const float size = mesh.bounds().diagonal();
  auto unit = [&]() {
    glm::vec3 v;
    do {
      v = {gauss(rng), gauss(rng), gauss(rng)};
    } while (glm::length(v) < 1e-3f);
    return glm::normalize(v);
  };
  const glm::vec3 d = unit();
  glm::vec3 m = unit();
  m = glm::normalize(m - glm::dot(m, d) * d + 1e-3f * unit());
  const float blade = size * (0.05f + 0.3f * u01(rng)), sweep = size * (0.03f + 0.3f * u01(rng));
  Blade s, e;
  s.handle = c - 0.5f * blade * d - 0.5f * sweep * m;
  s.tip = s.handle + blade * d;
  glm::vec3 d2 = d;
  if (twisted) d2 = glm::normalize(d + 0.4f * unit());
  e.handle = s.handle + sweep * m;
  e.tip = e.handle + blade * d2;
  return {s, e};
}

std::string debug_edge(const SurfaceMesh& mesh, const SurfaceMesh& input, const TearResult& r,
                       const std::vector<Tri3>& quad, std::uint32_t a, std::uint32_t b) {
  std::ostringstream o;
  o << "\n quad tris " << quad.size() << " input verts " << input.vertex_count();
  for (auto v : {a, b}) {
    o << "\n v" << v << " tear "
      << std::binary_search(r.tear_vertices.begin(), r.tear_vertices.end(), VertexId(v));
    for (const auto& t : quad) {
      const glm::dvec3 n = glm::normalize(glm::cross(glm::dvec3(t[1] - t[0]), glm::dvec3(t[2] - t[0])));
      o << " d=" << glm::dot(glm::dvec3(mesh.positions()[v]) - glm::dvec3(t[0]), n);
      if (v < input.vertex_count())
        o << " (was " << glm::dot(glm::dvec3(input.positions()[v]) - glm::dvec3(t[0]), n) << ")";
    }
    for (const Edit& e : r.log.edits) {
      if (const auto* m = std::get_if<VertexMoved>(&e); m && m->v.index == v)
        o << " moved " << glm::length(m->to - m->from);
      if (const auto* ad = std::get_if<VertexAdded>(&e); ad && ad->v.index == v)
        o << " added from " << ad->from[0].index << "," << ad->from[1].index << ","
          << (ad->from[2].valid() ? int(ad->from[2].index) : -1) << " w " << ad->weight[0] << ","
          << ad->weight[1] << "," << ad->weight[2];
      if (const auto* sp = std::get_if<VertexSplit>(&e);
          sp && (sp->copy.index == v || sp->original.index == v))
        o << " split " << sp->original.index << "->" << sp->copy.index;
    }
  }
  o << "\n width " << r.width;
  std::set<std::uint32_t> focus = {a, b};
  for (const Edit& e : r.log.edits)
    if (const auto* sp = std::get_if<VertexSplit>(&e);
        sp && (sp->copy.index == b || sp->original.index == b)) {
      focus.insert(sp->copy.index);
      focus.insert(sp->original.index);
    }
  for (auto v : focus) {
    o << "\n star of " << v << ":";
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      if (t[0].index != v && t[1].index != v && t[2].index != v) return;
      o << "\n   f" << f.index << " (";
      for (auto x : t) {
        o << x.index << "[";
        for (const auto& q : quad) {
          const glm::dvec3 n = glm::normalize(glm::cross(glm::dvec3(q[1] - q[0]), glm::dvec3(q[2] - q[0])));
          o << glm::dot(glm::dvec3(mesh.positions()[x.index]) - glm::dvec3(q[0]), n) << " ";
        }
        o << "] ";
      }
      o << ")";
    });
  }
  return o.str();
}

struct TearCheck {
  long new_loops = 0;  // boundary loops after minus before (a tear joining two borders merges them)
  TearResult result;
};

// All the invariants of one mesh-level tear in the bind pose.
void check_tear_into(TearCheck& out, SurfaceMesh& mesh, const Blade& start, const Blade& end,
                     const TearOptions& options, std::size_t joints, Adjacency* adjacency) {
  const SurfaceMesh input = mesh;
  const std::size_t loops_before = boundary_loops(input).size();
  const double size = input.bounds().diagonal();
  const double tol = options.relative_tolerance * size;
  const auto quad = swept_quad_triangles(start, end);
  out.result = tear_at_rest(mesh, start, end, options);
  const TearResult& r = out.result;
  if (r.status == OpStatus::NoIntersection) {
    EXPECT_TRUE(r.log.empty());
    EXPECT_EQ(mesh.faces(), input.faces());
    EXPECT_EQ(mesh.positions(), input.positions());
    return;
  }
  EXPECT_FALSE(r.tear_vertices.empty());
  if (adjacency) {
    adjacency->apply(r.log);
    test::expect_adjacency_matches_rebuild(*adjacency, mesh);
  }
  test::expect_valid(mesh, joints);
  const double w = r.width;
  // No live edge crosses the quad's interior.
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      const auto a = t[k].index, b = t[(k + 1) % 3].index;
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  });
  for (const auto& [a, b] : edges)
    ASSERT_FALSE(crosses_quad(mesh.positions()[a], mesh.positions()[b], quad, 2.0 * tol + 1e-6 * size))
        << "edge (" << a << "," << b << ") crosses the swept quad" << debug_edge(mesh, input, r, quad, a, b);
  // Boundary: closed loops only; the new ones near the quad, one per slit (two per closed slit).
  std::size_t open = 0;
  const auto loops = boundary_loops(mesh, &open);
  EXPECT_EQ(open, 0u) << "every boundary is a closed loop";
  const Adjacency before = Adjacency::build(input);
  std::set<std::uint32_t> old_boundary;
  for (const Edge& e : before.boundary_edges()) {
    old_boundary.insert(e.a.index);
    old_boundary.insert(e.b.index);
  }
  for (const auto& loop : loops)
    for (std::uint32_t v : loop) {
      if (v < input.vertex_count() && old_boundary.count(v)) continue;
      ASSERT_LE(quad_distance(mesh.positions()[v], quad), 0.5 * w + 4.0 * tol + 1e-6 * size)
          << "boundary vertex " << v << " is not on the slit";
    }
  out.new_loops = static_cast<long>(loops.size()) - static_cast<long>(loops_before);
  const long expected = static_cast<long>(r.slits + r.closed_slits);
  if (old_boundary.empty()) {
    EXPECT_EQ(out.new_loops, expected) << "one loop per slit (two per closed slit)";
  } else {
    EXPECT_LE(out.new_loops, expected) << "slits reaching a border join it";
  }
  // Area: re-triangulation keeps it; only the lip moves can change it, by at most what they sweep.
  std::map<std::uint32_t, double> moved;
  for (const Edit& e : r.log.edits)
    if (const auto* m = std::get_if<VertexMoved>(&e)) moved[m->v.index] += glm::length(m->to - m->from);
  double bound = 0.0;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      auto it = moved.find(t[k].index);
      if (it == moved.end()) continue;
      bound += 0.5 * it->second * glm::length(mesh.position(t[(k + 2) % 3]) - mesh.position(t[(k + 1) % 3]));
      bound += 0.5 * it->second * it->second;
    }
  });
  EXPECT_LE(std::abs(mesh.area() - input.area()), bound + 1e-5 * input.area())
      << "area change beyond the opening";
  // No face turned over: each keeps the orientation of the input face it came from.
  const auto root = face_roots(mesh, input.face_slots(), r.log);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const glm::dvec3 n0 = face_normal(input, input.face(FaceId(root[f.index])));
    const glm::dvec3 n1 = face_normal(mesh, t);
    if (glm::length(n0) < 1e-12 * size * size || glm::length(n1) < 1e-12 * size * size) return;
    ASSERT_GT(glm::dot(n0, n1), 0.0) << "face " << f.index << " turned over";
  });
  // Away from the quad nothing moves.
  for (std::uint32_t v = 0; v < input.vertex_count(); ++v) {
    if (quad_distance(input.positions()[v], quad) <= w + 4.0 * tol + 1e-6 * size) continue;
    ASSERT_EQ(mesh.positions()[v], input.positions()[v]) << "vertex " << v << " far from the blade moved";
  }
}

TearCheck check_tear(SurfaceMesh& mesh, const Blade& start, const Blade& end, const TearOptions& options,
                     std::size_t joints, Adjacency* adjacency = nullptr) {
  TearCheck out;
  check_tear_into(out, mesh, start, end, options, joints, adjacency);
  return out;
}

std::size_t loop_count(const SurfaceMesh& mesh) { return boundary_loops(mesh).size(); }

}  // namespace

TEST(TearTest, straight_tear_across_a_grid_opens_a_slit_that_ends_inside_faces) {
  SurfaceMesh mesh = test::make_grid(10, 10);
  const SurfaceMesh input = mesh;
  // A vertical blade (z from +1 to -1) dragged along y = 0.53 from x = 0.17 to x = 0.58.
  const Blade start{{0.17f, 0.53f, 1.0f}, {0.17f, 0.53f, -1.0f}};
  const Blade end{{0.58f, 0.53f, 1.0f}, {0.58f, 0.53f, -1.0f}};
  TearOptions options;
  options.width = 0.02f;
  Adjacency adj = Adjacency::build(mesh);
  const TearCheck c = check_tear(mesh, start, end, options, 2, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_EQ(c.result.slits, 1u);
  EXPECT_EQ(c.new_loops, 1);
  // The slit's two ends are new vertices inside faces (three sources each), at the blade's ends.
  std::vector<glm::vec3> ends;
  for (const Edit& e : c.result.log.edits)
    if (const auto* a = std::get_if<VertexAdded>(&e))
      if (a->from[2].valid() && a->weight[0] > 0 && a->weight[1] > 0 && a->weight[2] > 0)
        ends.push_back(mesh.position(a->v));
  ASSERT_EQ(ends.size(), 2u);
  std::sort(ends.begin(), ends.end(), [](const glm::vec3& a, const glm::vec3& b) { return a.x < b.x; });
  EXPECT_NEAR(ends[0].x, 0.17f, 1e-5f);
  EXPECT_NEAR(ends[1].x, 0.58f, 1e-5f);
  EXPECT_NEAR(ends[0].y, 0.53f, 1e-5f);
  // The opening: lip pairs split apart by up to the width, widest mid-way.
  double widest = 0.0, widest_x = 0.0;
  for (const Edit& e : c.result.log.edits)
    if (const auto* s = std::get_if<VertexSplit>(&e)) {
      const double gap = glm::length(mesh.position(s->original) - mesh.position(s->copy));
      if (gap > widest) {
        widest = gap;
        widest_x = mesh.position(s->original).x;
      }
    }
  EXPECT_GT(widest, 0.8 * options.width);
  EXPECT_LE(widest, options.width * 1.0001);
  EXPECT_NEAR(widest_x, 0.5 * (0.17 + 0.58), 0.1);
  // Beyond the blade's end (and before its start) the surface is untouched.
  for (std::uint32_t v = 0; v < input.vertex_count(); ++v) {
    const glm::vec3 p = input.positions()[v];
    if (p.x > 0.58f + 0.1f || p.x < 0.17f - 0.1f) {
      ASSERT_EQ(mesh.positions()[v], p);
    }
  }
  std::set<std::array<std::uint32_t, 3>> kept;
  mesh.for_each_face([&](FaceId, const Triangle& t) { kept.insert({t[0].index, t[1].index, t[2].index}); });
  input.for_each_face([&](FaceId, const Triangle& t) {
    bool beyond = true;
    for (auto v : t) beyond &= input.position(v).x > 0.58f + 0.1f;
    if (beyond) {
      EXPECT_TRUE(kept.count({t[0].index, t[1].index, t[2].index})) << "a face beyond the blade changed";
    }
  });
}

TEST(TearTest, degenerate_blades_are_rejected_and_misses_leave_the_mesh_untouched) {
  SurfaceMesh mesh = test::make_grid(4, 4);
  const SurfaceMesh input = mesh;
  const Blade a{{0.5f, 0.5f, 1.0f}, {0.5f, 0.5f, -1.0f}}, b{{0.7f, 0.5f, 1.0f}, {0.7f, 0.5f, -1.0f}};
  const Blade point{{0.5f, 0.5f, 1.0f}, {0.5f, 0.5f, 1.0f}};
  auto code = [&](const Blade& s, const Blade& e) {
    try {
      tear_at_rest(mesh, s, e);
    } catch (const Error& err) {
      return static_cast<int>(err.code());
    }
    return -1;
  };
  EXPECT_EQ(code(point, b), static_cast<int>(ErrorCode::InvalidArgument)) << "zero-length start blade";
  EXPECT_EQ(code(a, point), static_cast<int>(ErrorCode::InvalidArgument)) << "zero-length end blade";
  EXPECT_EQ(code(a, a), static_cast<int>(ErrorCode::InvalidArgument)) << "identical poses";
  const Blade along{{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, -0.5f}};
  const Blade along2{{0.5f, 0.5f, 0.9f}, {0.5f, 0.5f, -0.1f}};
  EXPECT_EQ(code(along, along2), static_cast<int>(ErrorCode::InvalidArgument)) << "blade moving along itself";
  const Blade nan{{NAN, 0.5f, 1.0f}, {0.5f, 0.5f, -1.0f}};
  EXPECT_EQ(code(nan, b), static_cast<int>(ErrorCode::InvalidArgument));
  PosedMesh three = PosedMesh::at_positions(mesh);
  three.posed.resize(3);
  EXPECT_THROW(tear_mesh(mesh, three, a, b), Error);
  EXPECT_EQ(mesh.faces(), input.faces());
  // Above the grid, and beside it: no intersection.
  for (float z : {2.0f, -3.0f}) {
    const Blade s{{0.2f, 0.5f, z}, {0.2f, 0.5f, z + 0.5f}}, e{{0.8f, 0.5f, z}, {0.8f, 0.5f, z + 0.5f}};
    const TearResult r = tear_at_rest(mesh, s, e);
    EXPECT_EQ(r.status, OpStatus::NoIntersection);
    EXPECT_TRUE(r.log.empty());
  }
  const Blade s{{2.2f, 0.5f, 1.0f}, {2.2f, 0.5f, -1.0f}}, e{{2.8f, 0.5f, 1.0f}, {2.8f, 0.5f, -1.0f}};
  EXPECT_EQ(tear_at_rest(mesh, s, e).status, OpStatus::NoIntersection);
  EXPECT_EQ(mesh.faces(), input.faces());
  EXPECT_EQ(mesh.positions(), input.positions());
}

TEST(TearTest, tear_through_grid_vertices_and_along_edges) {
  // The blade's plane runs through a row of vertices and along the grid's edges.
  SurfaceMesh mesh = test::make_grid(8, 8);
  const Blade start{{0.1f, 0.5f, 1.0f}, {0.1f, 0.5f, -1.0f}}, end{{0.9f, 0.5f, 1.0f}, {0.9f, 0.5f, -1.0f}};
  TearOptions options;
  options.width = 0.01f;
  Adjacency adj = Adjacency::build(mesh);
  const TearCheck c = check_tear(mesh, start, end, options, 2, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_EQ(c.result.slits, 1u);
  EXPECT_EQ(c.new_loops, 1);
  // Along the diagonal of the grid's squares (y = x), through vertices.
  SurfaceMesh diag = test::make_grid(8, 8);
  Adjacency adj2 = Adjacency::build(diag);
  const TearCheck d = check_tear(diag, {{0.2f, 0.2f, 1}, {0.2f, 0.2f, -1}},
                                 {{0.8f, 0.8f, 1}, {0.8f, 0.8f, -1}}, options, 2, &adj2);
  ASSERT_EQ(d.result.status, OpStatus::Ok);
  EXPECT_EQ(d.new_loops, 1);
}

// Found by the random sequences (zero-area faces after tears): a needle whose lone corner X lies
// on one side of the blade and whose two far corners lie one float step apart on the other. Both
// crossings round to one bind position; they become one vertex, and the needle's tip (a face with
// two corners at one point) is not made. The slit runs through the needle and ends inside its two
// flanking faces.
TEST(TearTest, a_needle_torn_near_its_tip_makes_no_zero_area_face) {
  for (const float width : {0.0f, 0.02f}) {
    SCOPED_TRACE(width);
    SurfaceMesh mesh = test::make_needle_fan();
    TearOptions options;
    options.width = width;
    Adjacency adj = Adjacency::build(mesh);
    const Blade start{{0.5f, 0.8f, 1.0f}, {0.5f, 0.8f, -1.0f}}, end{{0.5f, 1.2f, 1.0f}, {0.5f, 1.2f, -1.0f}};
    const TearCheck c = check_tear(mesh, start, end, options, 1, &adj);
    ASSERT_EQ(c.result.status, OpStatus::Ok);
    EXPECT_EQ(c.result.slits, 1u);
    EXPECT_EQ(c.new_loops, 1);
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      const glm::dvec3 u(mesh.position(t[0])), v(mesh.position(t[1])), w(mesh.position(t[2]));
      EXPECT_GT(glm::length(glm::cross(v - u, w - u)), 0.0) << "face " << f.index << " has zero area";
    });
    EXPECT_TRUE(adj.nonmanifold_edges().empty());
  }
}

// Found by the random sequences (RiggedFigure, a zero-area face after a tear): a needle whose
// two far corners lie a few float steps apart, near y = 0, torn across near its middle with a
// width. The two crossings stay apart (a sliver between them), but the opening moves both along
// the blade's normal, which has a y part: at the larger y they round onto one point and the
// sliver loses its area. Such a face keeps its lips where they were.
TEST(TearTest, opening_a_tear_across_a_needle_makes_no_zero_area_face) {
  for (int steps = 2; steps <= 8; steps += 2)
    for (const float width : {0.02f, 0.05f}) {
      SCOPED_TRACE("far corners " + std::to_string(steps) + " float steps apart, width " + std::to_string(width));
      SurfaceMesh mesh;
      float y = 1e-3f;
      for (int i = 0; i < steps; ++i) y = std::nextafter(y, 1.0f);
      const VertexId x = mesh.add_vertex({0, 0, 0}), p = mesh.add_vertex({1, -0.5f, 0}),
                     a = mesh.add_vertex({1, 1e-3f, 0}), b = mesh.add_vertex({1, y, 0}), q = mesh.add_vertex({1, 0.5f, 0});
      mesh.add_face(x, p, a);
      mesh.add_face(x, a, b);
      mesh.add_face(x, b, q);
      TearOptions options;
      options.width = width;
      Adjacency adj = Adjacency::build(mesh);
      // The blade's plane: normal (1, 1, 0) through (0.5, 5e-4, 0), swept across the needle.
      const glm::vec3 c(0.5f, 5e-4f, 0.0f), along(0.15f, -0.15f, 0.0f);
      const Blade start{c - along + glm::vec3(0, 0, 1), c - along - glm::vec3(0, 0, 1)};
      const Blade end{c + along + glm::vec3(0, 0, 1), c + along - glm::vec3(0, 0, 1)};
      const TearCheck t = check_tear(mesh, start, end, options, 1, &adj);
      ASSERT_EQ(t.result.status, OpStatus::Ok);
      EXPECT_EQ(t.result.slits, 1u);
      EXPECT_GT(t.result.opening, 0.0f);
      mesh.for_each_face([&](FaceId f, const Triangle& tri) {
        const glm::dvec3 u(mesh.position(tri[0])), v(mesh.position(tri[1])), w(mesh.position(tri[2]));
        EXPECT_GT(glm::length(glm::cross(v - u, w - u)), 0.0) << "face " << f.index << " has zero area";
      });
    }
}

TEST(TearTest, tear_from_the_border_opens_the_border) {
  SurfaceMesh mesh = test::make_grid(6, 6);
  TearOptions options;
  options.width = 0.02f;
  Adjacency adj = Adjacency::build(mesh);
  const TearCheck c = check_tear(mesh, {{-0.2f, 0.43f, 1}, {-0.2f, 0.43f, -1}},
                                 {{0.6f, 0.43f, 1}, {0.6f, 0.43f, -1}}, options, 2, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_EQ(loop_count(mesh), 1u) << "the slit joins the outer border: still one loop";
}

TEST(TearTest, tear_through_two_layers_tears_both) {
  // Two parallel sheets (a thin part): the blade crosses both.
  SurfaceMesh mesh = test::make_grid(8, 8);
  const SurfaceMesh other = test::make_grid(8, 8);
  const auto offset = static_cast<std::uint32_t>(mesh.vertex_count());
  for (const auto& p : other.positions()) mesh.add_vertex(p + glm::vec3(0, 0, 0.05f));
  auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  auto& j = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
  for (std::uint32_t v = 0; v < other.vertex_count(); ++v) {
    w[offset + v] = other.vertex_attrs().get<glm::vec4>(attr::kWeights0)[v];
    j[offset + v] = other.vertex_attrs().get<glm::u16vec4>(attr::kJoints0)[v];
  }
  other.for_each_face([&](FaceId, const Triangle& t) {
    mesh.add_face(VertexId(t[0].index + offset), VertexId(t[2].index + offset),
                  VertexId(t[1].index + offset));
  });
  TearOptions options;
  options.width = 0.01f;
  Adjacency adj = Adjacency::build(mesh);
  const TearCheck c = check_tear(mesh, {{0.2f, 0.47f, 1}, {0.2f, 0.47f, -1}},
                                 {{0.7f, 0.47f, 1}, {0.7f, 0.47f, -1}}, options, 2, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_EQ(c.result.slits, 2u);
  EXPECT_EQ(c.new_loops, 2);
}

TEST(TearTest, five_strokes_along_a_curve_give_one_slit) {
  SurfaceMesh mesh = test::make_grid(24, 24);
  TearOptions options;
  options.width = 0.01f;
  Adjacency adj = Adjacency::build(mesh);
  const std::size_t loops0 = loop_count(mesh);
  auto pose = [](double a) {
    const glm::vec3 c(0.5f + 0.3f * float(std::cos(a)), 0.2f + 0.3f * float(std::sin(a)), 0.0f);
    return Blade{c + glm::vec3(0, 0, 0.4f), c - glm::vec3(0, 0, 0.4f)};
  };
  for (int k = 0; k < 5; ++k) {
    SCOPED_TRACE("stroke " + std::to_string(k));
    const TearCheck c = check_tear(mesh, pose(0.5 + 0.25 * k), pose(0.5 + 0.25 * (k + 1)), options, 2, &adj);
    ASSERT_EQ(c.result.status, OpStatus::Ok);
    EXPECT_EQ(loop_count(mesh), loops0 + 1) << "each stroke extends the one slit";
  }
}

TEST(TearTest, strokes_on_the_cactus_trunk_give_one_slit_and_a_crossing_stroke_joins_it) {
  Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  ASSERT_EQ(model.meshes.size(), 1u);
  const SurfaceMesh input = model.meshes[0].primitives[0].mesh;
  const std::size_t loops0 = loop_count(input);
  // A blade pointing at the trunk's axis through its front wall only (it stops short of the arm
  // surfaces inside the trunk, at radius 0.66 and less), dragged along a curve.
  auto pose = [](double y, double phi) {
    const glm::vec3 dir(float(std::sin(phi)), 0.0f, float(std::cos(phi)));
    return Blade{glm::vec3(0.0f, float(y), 0.0f) + 1.6f * dir, glm::vec3(0.0f, float(y), 0.0f) + 0.7f * dir};
  };
  for (int k = 0; k < 5; ++k) {
    SCOPED_TRACE("stroke " + std::to_string(k));
    const auto y = [](int i) { return 3.0 + 0.3 * i; };
    const auto phi = [](int i) { return -0.3 + 0.15 * i - 0.02 * i * i; };
    const ModelTearResult r = tear_model(model, pose(y(k), phi(k)), pose(y(k + 1), phi(k + 1)));
    ASSERT_EQ(r.status, OpStatus::Ok);
    EXPECT_EQ(loop_count(model.meshes[0].primitives[0].mesh), loops0 + 1) << "the strokes make one slit";
  }
  // A stroke across the slit joins it: still one opening, no edge with more than two faces.
  const ModelTearResult r = tear_model(model, pose(3.45, -0.35), pose(3.45, 0.25));
  ASSERT_EQ(r.status, OpStatus::Ok);
  EXPECT_EQ(r.slits, 2u) << "the crossing stroke is cut in two by the slit";
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  EXPECT_EQ(loop_count(mesh), loops0 + 1);
  EXPECT_TRUE(Adjacency::build(mesh).nonmanifold_edges().empty());
  test::expect_valid(mesh, model.skins[0].joints.size());
}

TEST(TearTest, a_second_tear_crossing_the_first_gives_one_connected_opening) {
  SurfaceMesh mesh = test::make_grid(16, 16);
  TearOptions options;
  options.width = 0.02f;
  Adjacency adj = Adjacency::build(mesh);
  const std::size_t loops0 = loop_count(mesh);
  check_tear(mesh, {{0.2f, 0.52f, 1}, {0.2f, 0.52f, -1}}, {{0.8f, 0.52f, 1}, {0.8f, 0.52f, -1}}, options, 2,
             &adj);
  ASSERT_EQ(loop_count(mesh), loops0 + 1);
  const TearCheck c = check_tear(mesh, {{0.47f, 0.2f, 1}, {0.47f, 0.2f, -1}},
                                 {{0.47f, 0.8f, 1}, {0.47f, 0.8f, -1}}, options, 2, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_EQ(c.result.slits, 2u) << "the second tear is cut in two by the first slit";
  EXPECT_EQ(loop_count(mesh), loops0 + 1) << "one connected opening";
  // No edge is used by more than two faces and no face is repeated.
  const Adjacency rebuilt = Adjacency::build(mesh);
  EXPECT_TRUE(rebuilt.nonmanifold_edges().empty());
  std::set<std::array<std::uint32_t, 3>> seen;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    std::array<std::uint32_t, 3> k = {t[0].index, t[1].index, t[2].index};
    std::sort(k.begin(), k.end());
    EXPECT_TRUE(seen.insert(k).second) << "duplicate face";
  });
}

TEST(TearTest, twisted_blade_folds_the_quad_and_still_gives_one_slit) {
  SurfaceMesh mesh = test::make_grid(16, 16);
  TearOptions options;
  options.width = 0.01f;
  // The blade turns 60 degrees about the sweep direction while it moves.
  const Blade s{{0.2f, 0.5f, 0.5f}, {0.2f, 0.5f, -0.5f}};
  const Blade e{{0.8f, 0.5f + 0.43f, 0.25f}, {0.8f, 0.5f - 0.43f, -0.25f}};
  ASSERT_EQ(swept_quad_triangles(s, e).size(), 2u);
  Adjacency adj = Adjacency::build(mesh);
  const TearCheck c = check_tear(mesh, s, e, options, 2, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_EQ(c.result.slits, 1u);
  EXPECT_EQ(c.new_loops, 1);
}

// A small twisted blade folds its quad along a crease that crosses one big triangle of a box
// face: the crease vertex's wedges hold that triangle's far corners, one of them on the positive
// side of one facet's plane and the negative side of the other's, and nearer (counting the
// distance beyond the triangles) to the facet that puts it on the wrong side. Its lip must still
// open away from the quad, so that no edge of the opened mesh crosses the quad.
TEST(TearTest, a_folded_quad_creasing_inside_a_big_face_opens_each_lip_on_its_own_side) {
  SurfaceMesh mesh;
  for (const glm::vec3& p : {glm::vec3(1, -1, 1), glm::vec3(1, 1, 1), glm::vec3(-1, 1, 1), glm::vec3(-1, -1, 1),
                             glm::vec3(1, -1, -1), glm::vec3(-1, -1, -1), glm::vec3(-1, 1, -1), glm::vec3(1, 1, -1)})
    mesh.add_vertex(p);
  const std::array<std::uint32_t, 3> faces[] = {{0, 1, 2}, {3, 0, 2}, {4, 5, 6}, {7, 4, 6}, {5, 3, 2}, {6, 5, 2},
                                                {4, 0, 3}, {5, 4, 3}, {7, 1, 0}, {4, 7, 0}, {1, 7, 6}, {2, 1, 6}};
  for (const auto& f : faces) mesh.add_face(VertexId(f[0]), VertexId(f[1]), VertexId(f[2]));
  // The blade crosses the face x = 1 (through its triangle (7, 1, 0)), turning as it moves.
  const Blade start{{1.10994242f, 0.892425422f, -0.315780798f}, {1.11621544f, 0.724157551f, -0.0619761879f}};
  const Blade end{{0.883784052f, 0.792075694f, -0.376411201f}, {0.938921608f, 0.550922193f, -0.198717602f}};
  ASSERT_EQ(swept_quad_triangles(start, end).size(), 2u);
  Adjacency adj = Adjacency::build(mesh);
  const TearCheck c = check_tear(mesh, start, end, TearOptions{}, 0, &adj);
  ASSERT_EQ(c.result.status, OpStatus::Ok);
  EXPECT_GT(c.result.opening, 0.0f);
}

// Found by the random sequences (SimpleSkin seed 11 step 177 at aa5d4fd): a tear 1e-5 wide through
// a speck of tiny faces (a few tolerances across) of a model about 2 units tall. Each of its nine
// crossings lay within the tolerance of the next one in a face the slit crossed, so the close
// merges chained them all into one vertex: two pairs of faces became one triangle twice,
// reversed. A merge that would make a face twice (or use a directed edge twice) is refused.
TEST(TearTest, chained_close_merges_in_a_speck_of_tiny_faces_make_no_duplicate_face) {
  SurfaceMesh mesh;
  const glm::vec3 p[] = {
      {0x1.3df2cp-3f, 0x1.5bed02p+0f, 0x1.d16288p-16f}, {0x1.3e37bp-3f, 0x1.5bfa4cp+0f, 0x1.ecd5f6p-17f},
      {0x1.3e5a5p-3f, 0x1.5bfeep+0f, 0x1.291f5ep-18f},  {0x1.3df248p-3f, 0x1.5bec74p+0f, 0x1.c4f8e8p-16f},
      {0x1.3e191p-3f, 0x1.5beb08p+0f, 0x1.04db5ap-18f}, {0x1.3de7bp-3f, 0x1.5bec28p+0f, 0x1.bd1f2cp-16f},
      {0x1.3e0b08p-3f, 0x1.5bed0ep+0f, 0x1.f65be2p-17f}, {0x1.3e1738p-3f, 0x1.5bec42p+0f, 0x1.da5fdcp-18f},
      {0x1.3e36ap-3f, 0x1.5bf61p+0f, 0x1.044eaap-17f},  {0x1.3e1ap-3f, 0x1.5bf16ep+0f, 0x1.ee9beap-17f}};
  for (const glm::vec3& q : p) mesh.add_vertex(q);
  const std::array<std::uint32_t, 3> faces[] = {{1, 0, 2}, {0, 3, 6}, {0, 6, 9}, {8, 2, 0}, {4, 2, 8},
                                                {7, 8, 9}, {8, 7, 4}, {9, 6, 7}, {8, 0, 9}, {3, 0, 5}};
  for (const auto& f : faces) mesh.add_face(VertexId(f[0]), VertexId(f[1]), VertexId(f[2]));
  const Blade start{{0.15547019243240356f, 1.359025001525879f, 7.018661563051865e-05f},
                    {0.1554069072008133f, 1.359110713005066f, -0.00015965558122843504f}};
  const Blade end{{0.15519806742668152f, 1.359145164489746f, 0.000159528135554865f},
                  {0.15513478219509125f, 1.359230875968933f, -7.03140685800463e-05f}};
  TearOptions options;
  options.width = 1.0596721949696075e-05f;
  BoundingBox model;  // the whole model's bounds set the tolerance (2.1e-5 here)
  model.add(glm::vec3(0.0f));
  model.add(glm::vec3(0.0f, 2.15f, 0.0f));
  PosedMesh posed = PosedMesh::at_positions(mesh);
  posed.bounds = model;
  const TearResult r = tear_mesh(mesh, posed, start, end, options);
  ASSERT_EQ(r.status, OpStatus::Ok);
  test::expect_valid(mesh);
  std::set<std::array<std::uint32_t, 3>> seen;
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    std::array<std::uint32_t, 3> k = {t[0].index, t[1].index, t[2].index};
    std::sort(k.begin(), k.end());
    EXPECT_TRUE(seen.insert(k).second) << "face " << f.index << " (" << t[0].index << " " << t[1].index << " "
                                       << t[2].index << ") is made twice";
  });
  EXPECT_TRUE(Adjacency::build(mesh).nonmanifold_edges().empty());
}

TEST(TearTest, random_sweeps_on_every_asset_keep_all_invariants) {
  const unsigned seed = 20261122;
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path + " (seed " + std::to_string(seed) + ")");
    std::cout << "[ tear ] " << path << " seed " << seed << "\n";
    const Model model = read_gltf(path);
    const std::size_t joints = model.skins.empty() ? 0 : model.skins[0].joints.size();
    std::mt19937 rng(seed);
    std::size_t torn = 0;
    for (int i = 0; i < 100; ++i) {
      for (const auto& m : model.meshes)
        for (const auto& prim : m.primitives) {
          SCOPED_TRACE("sweep " + std::to_string(i));
          const auto [start, end] = random_sweep(prim.mesh, rng, i % 2 == 1);
          SurfaceMesh mesh = prim.mesh;
          TearOptions options;
          if (i % 3 == 0) options.width = 0.0f;
          const TearCheck c = check_tear(mesh, start, end, options, joints);
          torn += c.result.status == OpStatus::Ok;
          if (::testing::Test::HasFatalFailure()) return;
        }
    }
    EXPECT_GT(torn, 50u) << "most sweeps through a surface point tear it";
  }
}

// The random sweeps again, each at a random moment of the first clip (the rest pose when the
// model does not animate), through the instance as the posed model holds it: at that pose no
// mesh edge crosses the swept quad, and the new boundary runs along it.
TEST(TearTest, random_posed_sweeps_on_every_asset_leave_no_edge_across_the_quad) {
  const unsigned seed = 20261126;
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path + " (seed " + std::to_string(seed) + ")");
    const Model model = read_gltf(path);
    const std::size_t joints = model.skins.empty() ? 0 : model.skins[0].joints.size();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    std::size_t torn = 0;
    for (int i = 0; i < 40; ++i) {
      SCOPED_TRACE("sweep " + std::to_string(i));
      const int animation = model.animations.empty() ? -1 : 0;
      const float time = animation < 0 ? 0.0f : u01(rng) * model.animations[0].duration();
      const PosedModel posed_model = PosedModel::build(model, animation, time);
      for (const auto& [key, inst] : posed_model.instances()) {
        const SurfaceMesh& source = model.meshes[inst.mesh].primitives[inst.primitive].mesh;
        SurfaceMesh at_pose = source;
        at_pose.positions() = inst.posed;
        const auto [start, end] = random_sweep(at_pose, rng, i % 2 == 1);
        SurfaceMesh mesh = source;
        PosedMesh posed = inst;
        TearOptions options;
        if (i % 3 == 0) options.width = 0.0f;
        const TearResult r = tear_mesh(mesh, posed, start, end, options);
        if (r.status != OpStatus::Ok) continue;
        ++torn;
        test::expect_valid(mesh, joints);
        const double size = inst.bounds.diagonal(), tol = options.relative_tolerance * size;
        const auto quad = swept_quad_triangles(start, end);
        std::size_t crossing = 0;
        mesh.for_each_face([&](FaceId, const Triangle& t) {
          for (int k = 0; k < 3; ++k)
            crossing += crosses_quad(posed.posed[t[k].index], posed.posed[t[(k + 1) % 3].index], quad,
                                     2.0 * tol + 1e-6 * size);
        });
        EXPECT_EQ(crossing, 0u) << "half-edges crossing the swept quad at t = " << time;
        const Adjacency before = Adjacency::build(source);
        std::set<std::uint32_t> old_boundary;
        for (const Edge& e : before.boundary_edges()) old_boundary.insert({e.a.index, e.b.index});
        for (const auto& loop : boundary_loops(mesh))
          for (std::uint32_t v : loop) {
            if (old_boundary.count(v)) continue;
            ASSERT_LE(quad_distance(posed.posed[v], quad), 0.5 * r.width + 4.0 * tol + 1e-6 * size)
                << "boundary vertex " << v << " is not on the slit at t = " << time;
          }
        if (::testing::Test::HasFatalFailure()) return;
      }
    }
    EXPECT_GT(torn, 20u) << "most sweeps through a surface point tear it";
  }
}

TEST(TearTest, random_tear_sequences_keep_incremental_adjacency_equal_to_a_rebuild) {
  const unsigned seed = 77;
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path + " (seed " + std::to_string(seed) + ")");
    const Model model = read_gltf(path);
    const std::size_t joints = model.skins.empty() ? 0 : model.skins[0].joints.size();
    std::mt19937 rng(seed);
    SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
    Adjacency adj = Adjacency::build(mesh);
    for (int i = 0; i < 12; ++i) {
      SCOPED_TRACE("tear " + std::to_string(i));
      const auto [start, end] = random_sweep(mesh, rng, i % 3 == 2);
      check_tear(mesh, start, end, {}, joints, &adj);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

TEST(TearTest, posed_tear_opens_where_the_designer_saw_it) {
  Model model = test::make_skinned_tube_model();
  const auto world = world_matrices(model, sample_pose(model, 0, 1.0f));  // bent 60 degrees
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  const std::vector<glm::vec3> posed = posed_positions(model, 0, mesh, world);
  // A blade through the near wall of the bent upper half, dragged along the tube (in the pose).
  const glm::vec3 q = posed[6 * 16 + 4], top = posed[8 * 16 + 4];  // vertices at angle 90 degrees
  const glm::vec3 along = glm::normalize(top - q), out(0.0f, 0.0f, -1.0f);
  const Blade start{q - 0.5f * along + 0.4f * out, q - 0.5f * along - 0.3f * out};
  const Blade end{q + 0.5f * along + 0.4f * out, q + 0.5f * along - 0.3f * out};
  TearOptions options;
  options.width = 0.05f;
  const ModelTearResult r = tear_model(model, start, end, options, 0, 1.0f);
  ASSERT_EQ(r.status, OpStatus::Ok);
  EXPECT_EQ(r.slits, 1u);
  const SurfaceMesh& after = model.meshes[0].primitives[0].mesh;
  test::expect_valid(after, 2);
  const auto reposed = posed_positions(model, 0, after, world);
  const auto quad = swept_quad_triangles(start, end);
  ASSERT_EQ(quad.size(), 2u);
  const glm::dvec3 n =
      glm::normalize(glm::cross(glm::dvec3(quad[0][1] - quad[0][0]), glm::dvec3(quad[0][2] - quad[0][0])));
  // In the pose, the slit lies on the quad and its lips stand apart on both sides of it.
  const auto loops = boundary_loops(after);
  ASSERT_EQ(loops.size(), 1u);
  double far = 0.0, lo = 0.0, hi = 0.0;
  for (std::uint32_t v : loops[0]) {
    far = std::max(far, quad_distance(reposed[v], quad));
    const double d = glm::dot(glm::dvec3(reposed[v]) - glm::dvec3(quad[0][0]), n);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  EXPECT_LE(far, 0.5 * options.width + 1e-3);
  EXPECT_GT(hi, 0.35 * options.width) << "the opening shows in the pose";
  EXPECT_LT(lo, -0.35 * options.width) << "the opening shows in the pose";
  // The same blade in the bind pose would be elsewhere: the bind-space slit is not on the quad.
  double bind_far = 0.0;
  for (std::uint32_t v : loops[0]) bind_far = std::max(bind_far, quad_distance(after.positions()[v], quad));
  EXPECT_GT(bind_far, 0.1);
}

TEST(TearTest, model_tears_export_animated_files_that_pass_the_validator) {
  const std::string dir = test::temp_dir("tearmodel");
  std::vector<std::string> outputs;
  std::mt19937 rng(11);
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path);
    const Model original = read_gltf(path);
    int node = -1;
    for (std::size_t n = 0; n < original.nodes.size(); ++n)
      if (original.nodes[n].mesh >= 0) node = static_cast<int>(n);
    ASSERT_GE(node, 0);
    const auto world = world_matrices(original, rest_pose(original));
    SurfaceMesh posed_mesh = original.meshes[original.nodes[node].mesh].primitives[0].mesh;
    posed_mesh.positions() = posed_positions(original, node, posed_mesh, world);
    Model model = original;
    int torn = 0;
    for (int i = 0; i < 4; ++i) {
      const auto [start, end] = random_sweep(posed_mesh, rng, i % 2 == 1);
      const ModelTearResult r = tear_model(model, start, end, {});
      torn += r.status == OpStatus::Ok;
    }
    EXPECT_GT(torn, 0);
    for (const auto& m : model.meshes)
      for (const auto& p : m.primitives)
        test::expect_valid(p.mesh, original.skins.empty() ? 0 : original.skins[0].joints.size());
    const std::string out =
        dir + "/" + std::filesystem::path(path).stem().string() + (outputs.size() % 2 ? ".gltf" : ".glb");
    write_gltf(model, out);
    outputs.push_back(out);
    const Model again = read_gltf(out);
    EXPECT_EQ(again.skins.size(), original.skins.size());
    EXPECT_EQ(again.animations.size(), original.animations.size());
  }
  std::string files;
  for (const auto& o : outputs) files += " " + test::quote(o);
  const auto v = test::run_command("node " + test::quote(DEEPCUT_VALIDATOR_SCRIPT) + files);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  std::filesystem::remove_all(dir);
}

}  // namespace deepcut

namespace deepcut {
namespace {

// Faces (in slot order, deleted ones marked) and positions: what two tears must agree on.
struct MeshState {
  std::vector<Triangle> faces;
  std::vector<bool> deleted;
  std::vector<glm::vec3> positions;
  bool operator==(const MeshState& o) const {
    return faces == o.faces && deleted == o.deleted && positions == o.positions;
  }
};
MeshState state_of(const SurfaceMesh& mesh) {
  MeshState s{mesh.faces(), {}, mesh.positions()};
  for (std::size_t f = 0; f < mesh.face_slots(); ++f) s.deleted.push_back(mesh.is_deleted(FaceId(std::uint32_t(f))));
  return s;
}

// Tears `strokes` in a row on two copies of `input`, one on a PosedMesh built afresh before each
// stroke and one on a PosedMesh that followed the earlier strokes (tear_mesh keeps it up to date
// from its log): the results must be the same, stroke by stroke.
void expect_followed_posed_mesh_gives_the_same_tears(const SurfaceMesh& input,
                                                     const std::vector<std::pair<Blade, Blade>>& strokes,
                                                     const TearOptions& options) {
  SurfaceMesh fresh = input, followed = input;
  PosedMesh posed = PosedMesh::at_positions(followed);
  for (std::size_t i = 0; i < strokes.size(); ++i) {
    SCOPED_TRACE("stroke " + std::to_string(i));
    const TearResult a = tear_at_rest(fresh, strokes[i].first, strokes[i].second, options);
    const TearResult b = tear_mesh(followed, posed, strokes[i].first, strokes[i].second, options);
    ASSERT_EQ(posed.posed, followed.positions());
    ASSERT_EQ(a.status, OpStatus::Ok);
    ASSERT_EQ(b.status, OpStatus::Ok);
    EXPECT_EQ(a.intersection_points, b.intersection_points);
    EXPECT_EQ(a.tear_vertices, b.tear_vertices);
    EXPECT_EQ(a.slits, b.slits);
    EXPECT_EQ(a.opening, b.opening);
    EXPECT_EQ(a.log.size(), b.log.size());
    ASSERT_TRUE(state_of(fresh) == state_of(followed));
  }
}

}  // namespace

TEST(TearTest, a_posed_mesh_followed_through_earlier_tears_gives_the_same_tears_as_a_fresh_one) {
  Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const SurfaceMesh cactus = model.meshes[0].primitives[0].mesh;
  auto pose = [](double y, double phi) {
    const glm::vec3 dir(float(std::sin(phi)), 0.0f, float(std::cos(phi)));
    return Blade{glm::vec3(0.0f, float(y), 0.0f) + 1.6f * dir, glm::vec3(0.0f, float(y), 0.0f) + 0.7f * dir};
  };
  std::vector<std::pair<Blade, Blade>> strokes;
  for (int k = 0; k < 4; ++k) strokes.emplace_back(pose(3.0 + 0.3 * k, -0.3 + 0.15 * k), pose(3.3 + 0.3 * k, -0.15 + 0.15 * k));
  strokes.emplace_back(pose(3.45, -0.35), pose(3.45, 0.25));  // across the slit
  expect_followed_posed_mesh_gives_the_same_tears(cactus, strokes, {});
  // A twisted blade (the quad folds into two planar pieces) on a grid, twice in a row.
  const SurfaceMesh grid = test::make_grid(24, 24);
  TearOptions narrow;
  narrow.width = 0.01f;
  expect_followed_posed_mesh_gives_the_same_tears(grid,
                                    {{{{0.2f, 0.3f, 1}, {0.2f, 0.3f, -1}}, {{0.8f, 0.6f, 1}, {0.8f, 0.4f, -1}}},
                                     {{{0.5f, 0.1f, 1}, {0.5f, 0.1f, -1}}, {{0.55f, 0.9f, -1}, {0.45f, 0.9f, 1}}}},
                                    narrow);
}

}  // namespace deepcut
