// SPDX-License-Identifier: MIT
// Clusters following edit logs (Clusters::apply): never a re-clustering, always the invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/tear.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/softbody/simulation.h"
#include "fixtures.h"

namespace deepcut {
namespace {

const std::string kCactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";

std::string first_problems(const std::vector<std::string>& problems) {
  std::string out;
  for (std::size_t i = 0; i < problems.size() && i < 5; ++i) out += "\n  " + problems[i];
  return out;
}

void expect_invariants(const Clusters& c, const SurfaceMesh& mesh) {
  const auto problems = check_clusters(c, mesh, mesh.positions());
  EXPECT_TRUE(problems.empty()) << first_problems(problems);
  EXPECT_EQ(cluster_stats(c, mesh).uncovered_vertices, 0u);
}

/// Every particle's members lie in one connected component of the mesh (from a fresh
/// adjacency), i.e. no particle holds vertices of two pieces.
void expect_no_particle_spans_pieces(const Clusters& c, const SurfaceMesh& mesh) {
  std::size_t count = 0;
  const auto component = Adjacency::build(mesh).vertex_components(&count);
  for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
    const auto& m = c.members(p);
    for (std::uint32_t v : m)
      ASSERT_EQ(component[v], component[m.front()])
          << "particle " << p << " holds vertices " << m.front() << " and " << v << " of different pieces";
  }
}

void expect_same_clusters(const Clusters& a, const Clusters& b) {
  ASSERT_EQ(a.particle_slots(), b.particle_slots());
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  for (std::uint32_t p = 0; p < a.particle_slots(); ++p) {
    EXPECT_EQ(a.members(p), b.members(p)) << "particle " << p;
    EXPECT_EQ(a.seed(p), b.seed(p));
  }
  for (std::uint32_t v = 0; v < a.vertex_count(); ++v) {
    const InfluenceRange ra = a.influences(VertexId(v)), rb = b.influences(VertexId(v));
    ASSERT_EQ(ra.size(), rb.size()) << "vertex " << v;
    for (std::size_t i = 0; i < ra.size(); ++i) {
      EXPECT_EQ(ra.begin()[i].particle, rb.begin()[i].particle);
      EXPECT_FLOAT_EQ(ra.begin()[i].weight, rb.begin()[i].weight);
    }
  }
}

/// The particles present before an edit keep their seeds: apply never re-clusters.
void expect_original_seeds_kept(const Clusters& before, const Clusters& after) {
  ASSERT_GE(after.particle_slots(), before.particle_slots());
  for (std::uint32_t p = 0; p < before.particle_slots(); ++p) EXPECT_EQ(before.seed(p), after.seed(p));
}

// Tube faces are added ring row by ring row: row j, column i gives faces 2 (j * around + i) + {0, 1}.
FaceId tube_face(int around, int j, int i, int k) {
  return FaceId(static_cast<std::uint32_t>(2 * (j * around + i) + k));
}

TEST(SoftbodyUpdateTest, removing_a_band_splits_particles_into_the_two_pieces) {
  const int around = 24, along = 30;
  SurfaceMesh mesh = test::make_tube(around, along, 1.0f, 6.0f);  // rings 0.2 apart
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.8f});
  const Clusters before = clusters;
  Adjacency adjacency = Adjacency::build(mesh);
  MeshEditor editor(mesh);
  for (int j = 14; j <= 15; ++j)
    for (int i = 0; i < around; ++i)
      for (int k = 0; k < 2; ++k) editor.remove_face(tube_face(around, j, i, k));
  const EditLog log = editor.take_log();
  adjacency.apply(log);
  ASSERT_EQ(adjacency.component_count(), 2u);

  Clusters scanned = clusters;
  const ClusterUpdate update = clusters.apply(mesh, log, &adjacency);
  const ClusterUpdate update_scanned = scanned.apply(mesh, log);
  expect_invariants(clusters, mesh);
  expect_no_particle_spans_pieces(clusters, mesh);
  expect_same_clusters(clusters, scanned);
  expect_original_seeds_kept(before, clusters);
  EXPECT_EQ(update.vertices_removed, std::size_t(around));  // ring 15 has no face left
  EXPECT_EQ(update.vertices_added, 0u);
  EXPECT_GT(update.particles_split, 0u);
  EXPECT_EQ(update.touched, update_scanned.touched);
  for (int i = 0; i < around; ++i)
    EXPECT_TRUE(clusters.influences(VertexId(static_cast<std::uint32_t>(15 * around + i))).empty());
  // Untouched particles keep their centres; touched ones moved to their members' mean.
  for (std::uint32_t p = 0; p < before.particle_slots(); ++p)
    if (!std::binary_search(update.touched.begin(), update.touched.end(), p)) {
      EXPECT_EQ(clusters.rest_centre(p), before.rest_centre(p));
    }
}

TEST(SoftbodyUpdateTest, split_vertices_join_the_same_particles_then_separate) {
  // Tear the tube around ring 15: every ring vertex is split and the row above uses the copies.
  const int around = 20, along = 30;
  SurfaceMesh mesh = test::make_tube(around, along, 1.0f, 6.0f);
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.7f});
  Adjacency adjacency = Adjacency::build(mesh);
  MeshEditor editor(mesh);
  std::vector<VertexId> copies;
  for (int i = 0; i < around; ++i)
    copies.push_back(editor.split_vertex(VertexId(static_cast<std::uint32_t>(15 * around + i))));
  for (int i = 0; i < around; ++i)
    for (int k = 0; k < 2; ++k) {
      const FaceId f = tube_face(around, 15, i, k);
      Triangle t = mesh.face(f);
      for (auto& v : t)
        if (v.index / around == 15u) v = copies[v.index % around];
      editor.remove_face(f);
      editor.add_face_from(t, f, {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)});
    }
  const EditLog log = editor.take_log();
  adjacency.apply(log);
  ASSERT_EQ(adjacency.component_count(), 2u);
  std::vector<std::vector<std::uint32_t>> original_particles(around);
  for (int i = 0; i < around; ++i)
    for (const Influence& in : clusters.influences(VertexId(static_cast<std::uint32_t>(15 * around + i))))
      original_particles[i].push_back(in.particle);

  const ClusterUpdate update = clusters.apply(mesh, log, &adjacency);
  expect_invariants(clusters, mesh);
  expect_no_particle_spans_pieces(clusters, mesh);
  EXPECT_EQ(update.vertices_added, std::size_t(around));
  EXPECT_GT(update.particles_split, 0u);
  std::size_t count = 0;
  const auto component = adjacency.vertex_components(&count);
  for (int i = 0; i < around; ++i) {
    const VertexId original(static_cast<std::uint32_t>(15 * around + i));
    const VertexId copy = copies[i];
    ASSERT_FALSE(clusters.influences(copy).empty());
    ASSERT_FALSE(clusters.influences(original).empty());
    EXPECT_NE(component[original.index], component[copy.index]);
    // Original and copy share no particle any more.
    for (const Influence& a : clusters.influences(original))
      for (const Influence& b : clusters.influences(copy)) EXPECT_NE(a.particle, b.particle);
    // The copy joined its original's particles: it is in one of them, or in a part split off one.
    for (const Influence& b : clusters.influences(copy)) {
      std::uint32_t q = b.particle;
      for (const auto& c : update.created)
        if (c.particle == q) q = c.parent;
      const auto& from = original_particles[i];
      EXPECT_NE(std::find(from.begin(), from.end(), q), from.end())
          << "copy " << copy.index << " in particle " << b.particle;
    }
  }
}

TEST(SoftbodyUpdateTest, added_vertex_interpolates_its_sources_influences) {
  SurfaceMesh mesh = test::make_grid(20, 20);
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.3f});
  const FaceId f(200);
  const Triangle t = mesh.face(f);
  const glm::vec3 bary(0.2f, 0.3f, 0.5f);
  // Expected: sum_i bary_i * w(t_i, p), restricted to seeds within rho, renormalised.
  std::vector<std::pair<std::uint32_t, double>> expected;
  for (int i = 0; i < 3; ++i)
    for (const Influence& in : clusters.influences(t[i])) {
      auto it = std::find_if(expected.begin(), expected.end(),
                             [&](const auto& e) { return e.first == in.particle; });
      if (it == expected.end())
        expected.emplace_back(in.particle, bary[i] * in.weight);
      else
        it->second += bary[i] * in.weight;
    }
  const glm::vec3 p =
      bary.x * mesh.position(t[0]) + bary.y * mesh.position(t[1]) + bary.z * mesh.position(t[2]);
  expected.erase(
      std::remove_if(expected.begin(), expected.end(),
                     [&](const auto& e) { return glm::length(p - clusters.seed(e.first)) > 0.3f; }),
      expected.end());
  double sum = 0.0;
  for (const auto& e : expected) sum += e.second;
  ASSERT_GT(sum, 0.0);

  MeshEditor editor(mesh);
  const VertexId c = editor.add_vertex_in_triangle(t, bary);
  editor.remove_face(f);
  const glm::vec3 e0(1, 0, 0), e1(0, 1, 0), e2(0, 0, 1);
  editor.add_face_from({t[0], t[1], c}, f, {e0, e1, bary});
  editor.add_face_from({t[1], t[2], c}, f, {e1, e2, bary});
  editor.add_face_from({t[2], t[0], c}, f, {e2, e0, bary});
  const ClusterUpdate update = clusters.apply(mesh, editor.take_log());
  expect_invariants(clusters, mesh);
  EXPECT_EQ(update.vertices_added, 1u);
  EXPECT_TRUE(update.created.empty());
  const InfluenceRange row = clusters.influences(c);
  ASSERT_EQ(row.size(), expected.size());
  for (const Influence& in : row) {
    auto it =
        std::find_if(expected.begin(), expected.end(), [&](const auto& e) { return e.first == in.particle; });
    ASSERT_NE(it, expected.end()) << "unexpected particle " << in.particle;
    EXPECT_NEAR(in.weight, it->second / sum, 1e-5);
    const auto& m = clusters.members(in.particle);
    EXPECT_TRUE(std::binary_search(m.begin(), m.end(), c.index));
  }
}

TEST(SoftbodyUpdateTest, moved_vertex_leaves_particles_beyond_rho) {
  SurfaceMesh mesh = test::make_grid(20, 20);
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.2f});
  const VertexId v(10 * 21 + 10);  // (0.5, 0.5)
  const InfluenceRange before = clusters.influences(v);
  std::vector<std::uint32_t> old_particles;
  for (const Influence& in : before) old_particles.push_back(in.particle);
  MeshEditor editor(mesh);
  editor.move_vertex(v, mesh.position(v) + glm::vec3(0.0f, 0.0f, 0.6f));  // 0.6 from every seed
  const ClusterUpdate update = clusters.apply(mesh, editor.take_log());
  expect_invariants(clusters, mesh);
  ASSERT_EQ(clusters.influences(v).size(), 1u);
  const std::uint32_t p = clusters.influences(v).begin()->particle;
  EXPECT_EQ(std::find(old_particles.begin(), old_particles.end(), p), old_particles.end());
  ASSERT_EQ(update.created.size(), 1u);
  EXPECT_EQ(update.created[0].particle, p);
  EXPECT_FALSE(update.created[0].parent < clusters.particle_slots());
  for (std::uint32_t q : old_particles) {
    EXPECT_TRUE(std::binary_search(update.touched.begin(), update.touched.end(), q));
    EXPECT_FALSE(std::binary_search(clusters.members(q).begin(), clusters.members(q).end(), v.index));
  }
}

// Random local edits through MeshEditor: 1-to-3 face splits, edge splits (every face of the
// edge), vertex splits with one face re-attached to the copy, face removals, vertex moves.
void random_edit(SurfaceMesh& mesh, MeshEditor& editor, const Adjacency& adj, std::mt19937& rng) {
  std::vector<FaceId> live;
  mesh.for_each_face([&](FaceId f, const Triangle&) { live.push_back(f); });
  if (live.size() < 8) return;
  const FaceId f = live[std::uniform_int_distribution<std::size_t>(0, live.size() - 1)(rng)];
  const Triangle t = mesh.face(f);
  const glm::vec3 e0(1, 0, 0), e1(0, 1, 0), e2(0, 0, 1);
  switch (std::uniform_int_distribution<int>(0, 4)(rng)) {
    case 0: {
      const glm::vec3 b(0.3f, 0.3f, 0.4f);
      const VertexId c = editor.add_vertex_in_triangle(t, b);
      editor.remove_face(f);
      editor.add_face_from({t[0], t[1], c}, f, {e0, e1, b});
      editor.add_face_from({t[1], t[2], c}, f, {e1, e2, b});
      editor.add_face_from({t[2], t[0], c}, f, {e2, e0, b});
      break;
    }
    case 1: {
      const VertexId a = t[0], b = t[1];
      const auto faces = adj.edge_faces(a, b);
      const VertexId m = editor.add_vertex_on_edge(a, b, 0.4f);
      for (FaceId g : faces) {
        const Triangle gt = mesh.face(g);
        int ka = 0;
        while (gt[ka] != a) ++ka;
        const int kb = gt[(ka + 1) % 3] == b ? (ka + 1) % 3 : (ka + 2) % 3;
        const int kc = 3 - ka - kb;
        glm::vec3 ua(0.0f), ub(0.0f), uc(0.0f), um(0.0f);
        ua[ka] = 1;
        ub[kb] = 1;
        uc[kc] = 1;
        um[ka] = 0.6f;
        um[kb] = 0.4f;
        editor.remove_face(g);
        if (kb == (ka + 1) % 3) {
          editor.add_face_from({a, m, gt[kc]}, g, {ua, um, uc});
          editor.add_face_from({m, b, gt[kc]}, g, {um, ub, uc});
        } else {
          editor.add_face_from({b, m, gt[kc]}, g, {ub, um, uc});
          editor.add_face_from({m, a, gt[kc]}, g, {um, ua, uc});
        }
      }
      break;
    }
    case 2: {
      const VertexId copy = editor.split_vertex(t[0]);
      editor.remove_face(f);
      editor.add_face_from({copy, t[1], t[2]}, f, {e0, e1, e2});
      break;
    }
    case 3:
      editor.remove_face(f);
      break;
    default: {
      std::normal_distribution<float> gauss(0.0f, 0.15f);
      editor.move_vertex(t[1], mesh.position(t[1]) + glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
      break;
    }
  }
}

TEST(SoftbodyUpdateTest, random_edit_sequences_keep_every_invariant_without_reclustering) {
  std::mt19937 rng(1234);
  for (int round = 0; round < 3; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    SurfaceMesh mesh = test::make_tube(14, 10, 0.6f, 2.5f);
    Clusters with_adjacency = Clusters::build(mesh, ClusterOptions{0.35f + 0.2f * float(round)});
    const Clusters original = with_adjacency;
    Clusters scanning = with_adjacency;
    Adjacency adjacency = Adjacency::build(mesh);
    for (int op = 0; op < 120; ++op) {
      MeshEditor editor(mesh);
      EditLog log;
      const int batch = std::uniform_int_distribution<int>(1, 3)(rng);  // several edits per log
      for (int b = 0; b < batch; ++b) {
        random_edit(mesh, editor, adjacency, rng);
        const EditLog part = editor.take_log();
        adjacency.apply(part);
        log.append(part);
      }
      with_adjacency.apply(mesh, log, &adjacency);
      scanning.apply(mesh, log);
      const auto problems = check_clusters(with_adjacency, mesh, mesh.positions());
      ASSERT_TRUE(problems.empty()) << "after op " << op << first_problems(problems);
      ASSERT_EQ(cluster_stats(with_adjacency, mesh).uncovered_vertices, 0u);
    }
    expect_same_clusters(with_adjacency, scanning);
    expect_original_seeds_kept(original, with_adjacency);
    expect_no_particle_spans_pieces(with_adjacency, mesh);
  }
}

struct CutCase {
  Model model;
  SurfaceMesh* mesh = nullptr;
  int node = -1;
};

CutCase load_cactus() {
  CutCase c;
  c.model = read_gltf(kCactus);
  for (std::size_t n = 0; n < c.model.nodes.size(); ++n)
    if (c.model.nodes[n].mesh >= 0) {
      c.node = static_cast<int>(n);
      c.mesh = &c.model.meshes[c.model.nodes[n].mesh].primitives[0].mesh;
      break;
    }
  return c;
}

/// Every particle lies on one side of the cut: the piece of each vertex comes from the cut's
/// own piece lists.
void expect_no_particle_on_both_sides(const Clusters& c, const SurfaceMesh& mesh, const CutResult& cut) {
  std::vector<std::uint32_t> side(mesh.vertex_count(), kInvalidIndex);
  for (std::uint32_t k = 0; k < cut.pieces.size(); ++k)
    for (FaceId f : cut.pieces[k])
      for (const VertexId v : mesh.face(f)) {
        ASSERT_TRUE(side[v.index] == kInvalidIndex || side[v.index] == k)
            << "vertex " << v.index << " in two pieces";
        side[v.index] = k;
      }
  for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
    const auto& m = c.members(p);
    for (std::uint32_t v : m)
      ASSERT_EQ(side[v], side[m.front()]) << "particle " << p << " holds vertices of both sides of the cut";
  }
}

TEST(SoftbodyUpdateTest, after_a_cut_no_particle_holds_both_sides) {
  // Tear will feed the same Clusters::apply once it lands; this test covers cut.
  CutCase cc = load_cactus();
  ASSERT_NE(cc.mesh, nullptr);
  SurfaceMesh& mesh = *cc.mesh;
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.73f});
  const Clusters original = clusters;
  Adjacency adjacency = Adjacency::build(mesh);

  const Plane planes[] = {{{0.0f, 5.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},   // across the trunk
                          {{0.3f, 4.0f, 0.1f}, {1.0f, 0.3f, -0.2f}},  // oblique, through an arm joint
                          {{-0.2f, 2.5f, 0.0f}, {0.2f, -1.0f, 0.7f}}};
  for (const Plane& plane : planes) {
    const CutResult cut = cut_mesh(mesh, mesh.positions(), plane);
    ASSERT_EQ(cut.status, OpStatus::Ok);
    adjacency.apply(cut.log);
    Clusters scanning = clusters;
    const ClusterUpdate update = clusters.apply(mesh, cut.log, &adjacency);
    scanning.apply(mesh, cut.log);
    expect_invariants(clusters, mesh);
    expect_no_particle_on_both_sides(clusters, mesh, cut);
    expect_no_particle_spans_pieces(clusters, mesh);
    expect_same_clusters(clusters, scanning);
    EXPECT_GT(update.vertices_added, 0u);
    EXPECT_GT(update.particles_split, 0u);
    // The incremental result meets the same constraints as a re-clustering of the cut mesh.
    const Clusters fresh = Clusters::build(mesh, ClusterOptions{0.73f});
    expect_invariants(fresh, mesh);
    EXPECT_EQ(cluster_stats(clusters, mesh).covered_vertices, cluster_stats(fresh, mesh).covered_vertices);
  }
  expect_original_seeds_kept(original, clusters);
}

/// Lip pairs of a tear farther than 2 rho from both ends of the slit share no particle: a
/// particle's members lie within rho of its seed, so only a particle reaching round an end of the
/// slit could still connect the two lips. Returns how many pairs were checked.
std::size_t expect_lips_apart(const Clusters& c, const SurfaceMesh& mesh, const TearResult& tear) {
  std::vector<std::pair<VertexId, VertexId>> lips;
  for (const Edit& e : tear.log.edits)
    if (const auto* s = std::get_if<VertexSplit>(&e)) lips.emplace_back(s->original, s->copy);
  std::vector<VertexId> ends;
  for (const VertexId v : tear.tear_vertices) {
    const bool lip =
        std::any_of(lips.begin(), lips.end(), [&](const auto& l) { return l.first == v || l.second == v; });
    if (!lip) ends.push_back(v);
  }
  EXPECT_FALSE(ends.empty());
  std::size_t checked = 0;
  for (const auto& [a, b] : lips) {
    bool far = true;
    for (const VertexId e : ends)
      far = far && glm::length(mesh.position(a) - mesh.position(e)) > 2.0f * c.radius() + 0.1f;
    if (!far) continue;
    ++checked;
    for (const Influence& x : c.influences(a))
      for (const Influence& y : c.influences(b))
        EXPECT_NE(x.particle, y.particle)
            << "lips " << a.index << " and " << b.index << " share particle " << x.particle;
  }
  return checked;
}

TEST(SoftbodyUpdateTest, after_a_tear_no_particle_holds_both_lips) {
  SurfaceMesh mesh = test::make_tube(32, 40, 1.0f, 6.0f);
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.4f});
  const Clusters original = clusters;
  Adjacency adjacency = Adjacency::build(mesh);
  // A slit 4 units long down the +x wall of the tube.
  const Blade start{{2.0f, 1.0f, 0.05f}, {0.5f, 1.0f, 0.05f}}, end{{2.0f, 5.0f, 0.05f}, {0.5f, 5.0f, 0.05f}};
  PosedMesh posed = PosedMesh::at_positions(mesh);
  const TearResult tear = tear_mesh(mesh, posed, start, end);
  ASSERT_EQ(tear.status, OpStatus::Ok);
  ASSERT_EQ(tear.slits, 1u);
  adjacency.apply(tear.log);
  Clusters scanning = clusters;
  const ClusterUpdate update = clusters.apply(mesh, tear.log, &adjacency);
  scanning.apply(mesh, tear.log);
  expect_invariants(clusters, mesh);
  expect_same_clusters(clusters, scanning);
  expect_original_seeds_kept(original, clusters);
  EXPECT_GT(update.particles_split, 0u);
  EXPECT_GT(expect_lips_apart(clusters, mesh, tear), 10u);

  // A second stroke continuing the slit, then a cut through it: the updates chain.
  const Blade start2{{2.0f, 0.4f, 0.3f}, {0.5f, 0.4f, 0.3f}}, end2{{2.0f, 1.2f, 0.05f}, {0.5f, 1.2f, 0.05f}};
  PosedMesh posed2 = PosedMesh::at_positions(mesh);
  const TearResult tear2 = tear_mesh(mesh, posed2, start2, end2);
  ASSERT_EQ(tear2.status, OpStatus::Ok);
  adjacency.apply(tear2.log);
  clusters.apply(mesh, tear2.log, &adjacency);
  expect_invariants(clusters, mesh);
  const CutResult cut = cut_mesh(mesh, mesh.positions(), Plane{{0.0f, 3.0f, 0.0f}, {0.0f, 1.0f, 0.1f}});
  ASSERT_EQ(cut.status, OpStatus::Ok);
  adjacency.apply(cut.log);
  clusters.apply(mesh, cut.log, &adjacency);
  expect_invariants(clusters, mesh);
  expect_no_particle_on_both_sides(clusters, mesh, cut);
  expect_original_seeds_kept(original, clusters);
}

TEST(SoftbodyUpdateTest, after_a_tear_on_the_cactus_the_lips_separate) {
  CutCase cc = load_cactus();
  SurfaceMesh& mesh = *cc.mesh;
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.3f});
  // Down the front of the trunk (its surface crosses x = 0 at z ~0.74; the tip stays short of
  // the arms' roots inside the trunk, so this is one slit).
  const Blade start{{0.0f, 2.5f, 2.0f}, {0.0f, 2.5f, 0.65f}}, end{{0.0f, 6.5f, 2.0f}, {0.0f, 6.5f, 0.65f}};
  PosedMesh posed = PosedMesh::at_positions(mesh);
  const TearResult tear = tear_mesh(mesh, posed, start, end);
  ASSERT_EQ(tear.status, OpStatus::Ok);
  ASSERT_EQ(tear.slits, 1u);
  clusters.apply(mesh, tear.log);
  expect_invariants(clusters, mesh);
  EXPECT_GT(expect_lips_apart(clusters, mesh, tear), 10u);
}

TEST(SoftbodyUpdateTest, cut_in_an_animated_pose_keeps_the_invariants) {
  CutCase cc = load_cactus();
  SurfaceMesh& mesh = *cc.mesh;
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.6f});
  const auto world = world_matrices(cc.model, sample_pose(cc.model, 0, 1.0f));
  const auto posed = posed_positions(cc.model, cc.node, mesh, world);
  const CutResult cut = cut_mesh(mesh, posed, Plane{{0.0f, 6.0f, 0.0f}, {0.3f, 1.0f, 0.0f}});
  ASSERT_EQ(cut.status, OpStatus::Ok);
  clusters.apply(mesh, cut.log);
  expect_invariants(clusters, mesh);
  expect_no_particle_on_both_sides(clusters, mesh, cut);
}

TEST(SoftbodyUpdateTest, soft_body_state_follows_split_particles) {
  CutCase cc = load_cactus();
  SurfaceMesh& mesh = *cc.mesh;
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.73f});
  SoftBodyState state = make_soft_body(clusters);
  ASSERT_GT(poke(state, clusters, mesh.positions(), {0.9f, 5.0f, 0.0f}, {-4.0f, 0.0f, 0.0f}, 1.5f), 0u);
  step_soft_body(state, 1.0f / 30.0f);
  const SoftBodyState before = state;
  std::vector<glm::vec3> deformed_before;
  const std::vector<glm::vec3> rest_before = mesh.positions();
  deformed_positions(state, clusters, rest_before, deformed_before);
  const Clusters clusters_before = clusters;
  const CutResult cut = cut_mesh(mesh, mesh.positions(), Plane{{0.0f, 5.0f, 0.0f}, {0.0f, 1.0f, 0.0f}});

  const ClusterUpdate update = clusters.apply(mesh, cut.log);
  ASSERT_FALSE(update.created.empty());
  EXPECT_THROW(deformed_positions(state, clusters, mesh.positions(), deformed_before), Error)
      << "state not synced";
  sync_soft_body(state, clusters, update);
  ASSERT_EQ(state.displacement.size(), clusters.particle_slots());
  for (const auto& c : update.created) {
    ASSERT_LT(c.parent, before.displacement.size());
    EXPECT_EQ(state.displacement[c.particle], before.displacement[c.parent]);
    EXPECT_EQ(state.velocity[c.particle], before.velocity[c.parent]);
  }
  // Vertices whose particles were not touched keep exactly their displacement.
  std::vector<glm::vec3> deformed;
  deformed_positions(state, clusters, mesh.positions(), deformed);
  std::size_t compared = 0;
  for (std::uint32_t v = 0; v < clusters_before.vertex_count(); ++v) {
    bool untouched = !clusters.influences(VertexId(v)).empty();
    for (const Influence& in : clusters.influences(VertexId(v)))
      untouched = untouched && !std::binary_search(update.touched.begin(), update.touched.end(), in.particle);
    if (!untouched) continue;
    EXPECT_EQ(deformed[v] - mesh.positions()[v], deformed_before[v] - rest_before[v]);
    ++compared;
  }
  EXPECT_GT(compared, mesh.vertex_count() / 2);
  step_soft_body(state, 1.0f / 30.0f);
  for (const auto& p : state.displacement)
    EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

TEST(SoftbodyUpdateTest, rejects_logs_and_meshes_that_do_not_match) {
  SurfaceMesh mesh = test::make_grid(6, 6);
  Clusters clusters = Clusters::build(mesh, ClusterOptions{0.3f});
  EditLog bad;
  bad.edits.push_back(VertexSplit{VertexId(0), VertexId(1000)});
  EXPECT_THROW(clusters.apply(mesh, bad), Error);
  EditLog stale;  // names a face as removed that the mesh still has
  stale.edits.push_back(FaceRemoved{FaceId(0), mesh.face(FaceId(0))});
  EXPECT_THROW(clusters.apply(mesh, stale), Error);
  EditLog out_of_range;
  out_of_range.edits.push_back(FaceAdded{FaceId(5000), FaceId(), mesh.face(FaceId(0))});
  EXPECT_THROW(clusters.apply(mesh, out_of_range), Error);
  const std::vector<glm::vec3> short_rest(mesh.vertex_count() - 1);
  EXPECT_THROW(clusters.apply(mesh, short_rest, EditLog{}), Error);
  SurfaceMesh smaller = test::make_grid(3, 3);
  EXPECT_THROW(clusters.apply(smaller, EditLog{}), Error);
}

}  // namespace
}  // namespace deepcut
