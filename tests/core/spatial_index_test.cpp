// SPDX-License-Identifier: MIT
#include "deepcut/core/spatial_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "csr_fill.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "fixtures.h"
#include "parallel_beside.h"
#include "sorted_ids.h"

namespace deepcut {
namespace {

// Faces whose bounding box comes within `radius` of the segment a-b (brute force, with the
// box approximated by its corners' distance minus its half diagonal: a conservative test).
std::vector<FaceId> brute_capsule(const SurfaceMesh& mesh, const glm::vec3& a, const glm::vec3& b,
                                  float radius) {
  std::vector<FaceId> out;
  const glm::vec3 d = b - a;
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    // Distance from the segment to the triangle, sampled densely: a face within the capsule.
    bool near = false;
    for (int i = 0; i <= 20 && !near; ++i)
      for (int j = 0; i + j <= 20 && !near; ++j) {
        const float u = i / 20.0f, v = j / 20.0f;
        const glm::vec3 p =
            mesh.position(t[0]) * (1 - u - v) + mesh.position(t[1]) * u + mesh.position(t[2]) * v;
        const float s = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0f, 1.0f);
        near = glm::length(p - (a + s * d)) <= radius;
      }
    if (near) out.push_back(f);
  });
  return out;
}

}  // namespace

TEST(SpatialIndexTest, capsule_and_box_queries_contain_every_face_they_must) {
  SurfaceMesh mesh = test::make_tube(24, 12, 1.0f, 4.0f);
  const TriangleGrid grid = TriangleGrid::build(mesh, mesh.positions());
  EXPECT_EQ(grid.face_count(), mesh.face_count());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 50; ++i) {
    const glm::vec3 a(u(rng), u(rng) + 2.0f, u(rng)), b(u(rng), u(rng) + 2.0f, u(rng));
    const float radius = 0.05f + 0.1f * (i % 5);
    const auto got = grid.query_capsule(a, b, radius);
    EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
    for (FaceId f : brute_capsule(mesh, a, b, radius))
      EXPECT_TRUE(std::binary_search(got.begin(), got.end(), f))
          << "face " << f.index << " missing from the capsule query";
    EXPECT_LT(got.size(), mesh.face_count()) << "a thin capsule does not return the whole mesh";
  }
  BoundingBox box;
  box.add(glm::vec3(-0.2f, 1.0f, -2.0f));
  box.add(glm::vec3(0.2f, 1.5f, 2.0f));
  const auto in_box = grid.query_box(box);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    BoundingBox fb;
    for (auto v : t) fb.add(mesh.position(v));
    const bool overlap = fb.min.x <= box.max.x && fb.max.x >= box.min.x && fb.min.y <= box.max.y &&
                         fb.max.y >= box.min.y && fb.min.z <= box.max.z && fb.max.z >= box.min.z;
    if (overlap) {
      EXPECT_TRUE(std::binary_search(in_box.begin(), in_box.end(), f));
    }
  });
}

TEST(SpatialIndexTest, follows_the_edit_log) {
  SurfaceMesh mesh = test::make_grid(8, 8);
  TriangleGrid grid = TriangleGrid::build(mesh, mesh.positions());
  MeshEditor editor(mesh);
  // Split one face into three around its centre, far from the others.
  const FaceId f(10);
  const Triangle t = mesh.face(f);
  const VertexId c = editor.add_vertex_in_triangle(t, glm::vec3(1.0f / 3.0f));
  editor.remove_face(f);
  const glm::vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const glm::vec3 third(1.0f / 3.0f);
  editor.add_face_from({t[0], t[1], c}, f, {e[0], e[1], third});
  editor.add_face_from({t[1], t[2], c}, f, {e[1], e[2], third});
  editor.add_face_from({t[2], t[0], c}, f, {e[2], e[0], third});
  grid.apply(editor.take_log(), mesh.positions());
  EXPECT_EQ(grid.face_count(), mesh.face_count());
  BoundingBox everything = mesh.bounds();
  const auto all = grid.query_box(everything);
  std::vector<FaceId> live;
  mesh.for_each_face([&](FaceId g, const Triangle&) { live.push_back(g); });
  EXPECT_EQ(all, live) << "removed faces leave, added faces join";
  EXPECT_THROW(TriangleGrid::build(mesh, std::vector<glm::vec3>(3)), Error);
}

// A moved vertex (a drill snapping a vertex onto its cylinder, a tear's lips) changes the boxes of
// faces the log does not list: the grid finds them through the cell it filed them in.
TEST(SpatialIndexTest, faces_around_a_moved_vertex_are_found_at_their_new_place) {
  SurfaceMesh mesh = test::make_grid(8, 8);  // unit square, z = 0
  TriangleGrid grid = TriangleGrid::build(mesh, mesh.positions(), 0.05f);
  const VertexId v(4 * 9 + 4);  // the centre
  auto faces_using_v = [&] {
    std::vector<FaceId> out;
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      if (t[0] == v || t[1] == v || t[2] == v) out.push_back(f);
    });
    return out;
  };
  auto box_of = [&](FaceId f) {
    BoundingBox b;
    for (VertexId w : mesh.face(f)) b.add(mesh.position(w));
    return b;
  };
  ASSERT_EQ(faces_using_v().size(), 6u);
  // Twice, the second time from the place the first move left it (and in the same log as an
  // edit elsewhere).
  const glm::vec3 targets[2] = {{0.8f, 0.3f, 0.4f}, {0.2f, 0.9f, -0.3f}};
  for (std::uint32_t i = 0; i < 2; ++i) {
    const glm::vec3 to = targets[i];
    MeshEditor editor(mesh);
    editor.move_vertex(v, to);
    const FaceId far(i);
    const Triangle t = mesh.face(far);
    editor.remove_face(far);
    editor.add_face_from(t, far, {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)});
    grid.apply(editor.take_log(), mesh.positions());
    EXPECT_EQ(grid.face_count(), mesh.face_count());
    for (const FaceId f : faces_using_v()) {
      const auto found = grid.query_box(box_of(f));
      EXPECT_TRUE(std::binary_search(found.begin(), found.end(), f))
          << "face " << f.index << " around the moved vertex, at (" << to.x << ", " << to.y << ", " << to.z << ")";
      const auto capsule = grid.query_capsule(to, to, 0.01f);
      EXPECT_TRUE(std::binary_search(capsule.begin(), capsule.end(), f)) << "capsule at the new place";
    }
  }
}

TEST(SpatialIndexTest, slab_query_contains_every_face_near_the_plane_and_far_faces_added_later) {
  SurfaceMesh mesh = test::make_tube(32, 16, 1.0f, 4.0f);
  TriangleGrid grid = TriangleGrid::build(mesh, mesh.positions());
  // A face far outside the build bounds, added through the editor: it goes to a border cell.
  MeshEditor editor(mesh);
  const VertexId a = editor.add_vertex_on_edge(VertexId(0), VertexId(1), 0.5f);
  const VertexId b = editor.add_vertex_on_edge(VertexId(1), VertexId(2), 0.5f);
  const VertexId c = editor.add_vertex_on_edge(VertexId(2), VertexId(0), 0.5f);
  mesh.positions()[a.index] = {10.0f, 1.0f, 0.0f};
  mesh.positions()[b.index] = {10.5f, 1.0f, 0.0f};
  mesh.positions()[c.index] = {10.0f, 1.5f, 0.0f};
  editor.add_face({a, b, c});
  grid.apply(editor.take_log(), mesh.positions());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::size_t total = 0;
  for (int i = 0; i < 60; ++i) {
    const glm::vec3 point(u(rng), 2.0f + 2.0f * u(rng), u(rng));
    glm::vec3 normal(u(rng), u(rng), u(rng));
    if (i % 7 == 0) normal = {1.0f, 0.0f, 0.0f};  // axis-aligned: zero components
    if (glm::length(normal) < 0.1f) normal = {0.0f, 1.0f, 0.0f};
    const float half = 0.02f * float(i % 4);
    BoundingBox box;
    box.add(point - glm::vec3(1.5f + 20.0f * float(i % 2)));
    box.add(point + glm::vec3(1.5f + 20.0f * float(i % 2)));
    const auto got = grid.query_slab(box, point, normal, half);
    EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
    const glm::vec3 n = glm::normalize(normal);
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      BoundingBox fb;
      int above = 0, below = 0;
      for (auto v : t) {
        fb.add(mesh.position(v));
        const float d = glm::dot(mesh.position(v) - point, n);
        above += d > half;
        below += d < -half;
      }
      const bool overlap = fb.min.x <= box.max.x && fb.max.x >= box.min.x && fb.min.y <= box.max.y &&
                           fb.max.y >= box.min.y && fb.min.z <= box.max.z && fb.max.z >= box.min.z;
      if (overlap && above < 3 && below < 3) {
        ++total;
        EXPECT_TRUE(std::binary_search(got.begin(), got.end(), f)) << "face " << f.index << " missing, query " << i;
      }
    });
    EXPECT_LT(got.size(), grid.query_box(box).size() + 1);
  }
  EXPECT_GT(total, 100u) << "the planes meet the tube";
  // A slab through the far face finds it, one away from everything misses it.
  BoundingBox far;
  far.add(glm::vec3(9.0f, 0.0f, -1.0f));
  far.add(glm::vec3(11.0f, 2.0f, 1.0f));
  const auto hit = grid.query_slab(far, glm::vec3(10.2f, 1.2f, 0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.01f);
  EXPECT_TRUE(std::find(hit.begin(), hit.end(), FaceId(static_cast<std::uint32_t>(mesh.face_slots() - 1))) != hit.end());
}

// Capsule queries share one bitmap per thread (detail::IdMarks): a query must leave it clear, so
// the same query asked again after another gives the same faces. Also after `apply` added faces
// past the old slot count (the bitmap grows), and for a capsule holding low original ids and high
// new ones (sparse marks: the marked words are sorted, not the span scanned).
TEST(SpatialIndexTest, capsule_queries_repeat_after_other_queries_and_edits) {
  SurfaceMesh mesh = test::make_tube(128, 64, 1.0f, 4.0f);
  TriangleGrid grid = TriangleGrid::build(mesh, mesh.positions());
  const glm::vec3 a0(-2.0f, 2.0f, 0.0f), a1(2.0f, 2.0f, 0.0f), b0(0.0f, 0.5f, -2.0f), b1(0.0f, 3.5f, 2.0f);
  const auto check = [&](const std::vector<FaceId>& got, const glm::vec3& p, const glm::vec3& q, float r) {
    EXPECT_TRUE(std::adjacent_find(got.begin(), got.end(), [](FaceId x, FaceId y) { return !(x < y); }) ==
                got.end())
        << "sorted without repeats";
    for (const FaceId f : got) EXPECT_FALSE(mesh.is_deleted(f)) << "face " << f.index;
    for (const FaceId f : brute_capsule(mesh, p, q, r))
      EXPECT_TRUE(std::binary_search(got.begin(), got.end(), f)) << "face " << f.index << " missing";
  };
  const auto first = grid.query_capsule(a0, a1, 0.05f);
  check(first, a0, a1, 0.05f);
  const auto other = grid.query_capsule(b0, b1, 0.2f);
  check(other, b0, b1, 0.2f);
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(grid.query_capsule(a0, a1, 0.05f), first);
  EXPECT_EQ(grid.query_capsule(b0, b1, 0.2f), other);

  // Split a few faces of the first capsule into three: their pieces take ids past every old slot.
  const std::size_t old_slots = mesh.face_slots();
  MeshEditor editor(mesh);
  const glm::vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const glm::vec3 third(1.0f / 3.0f);
  for (std::size_t i = 0; i < first.size(); i += 7) {
    const FaceId f = first[i];
    const Triangle t = mesh.face(f);
    const VertexId c = editor.add_vertex_in_triangle(t, third);
    editor.remove_face(f);
    editor.add_face_from({t[0], t[1], c}, f, {e[0], e[1], third});
    editor.add_face_from({t[1], t[2], c}, f, {e[1], e[2], third});
    editor.add_face_from({t[2], t[0], c}, f, {e[2], e[0], third});
  }
  grid.apply(editor.take_log(), mesh.positions());
  ASSERT_GT(mesh.face_slots(), old_slots);
  const auto edited = grid.query_capsule(a0, a1, 0.05f);
  check(edited, a0, a1, 0.05f);
  ASSERT_FALSE(edited.empty());
  EXPECT_LT(edited.front().index, old_slots) << "original ids";
  EXPECT_GE(edited.back().index, old_slots) << "new ids";
  std::vector<std::uint32_t> words;
  for (const FaceId f : edited) words.push_back(f.index >> 6);
  words.erase(std::unique(words.begin(), words.end()), words.end());
  EXPECT_GE((edited.back().index >> 6) - (edited.front().index >> 6), 4 * words.size())
      << "ids spread far wider than their words: the sparse case";
  EXPECT_EQ(grid.query_capsule(b0, b1, 0.2f), other) << "the second capsule misses the edits";
  EXPECT_EQ(grid.query_capsule(a0, a1, 0.05f), edited);
}

// Marks left unread (an exception between marking and reading back) are cleared when the
// IdMarks goes: the thread's next use reads back only its own marks.
TEST(SpatialIndexTest, id_marks_left_unread_are_cleared) {
  {
    detail::IdMarks marks(0, 1u << 16);
    for (std::uint32_t id = 3; id < (1u << 16); id += 977) marks.mark(id);
  }
  detail::IdMarks marks(0, 1u << 16);
  marks.mark(5000);
  marks.mark(7);
  marks.mark(5000);
  marks.mark(60000);
  std::vector<FaceId> got;
  marks.take(got);
  EXPECT_EQ(got, (std::vector<FaceId>{FaceId(7), FaceId(5000), FaceId(60000)}));
  got.clear();
  marks.take(got);
  EXPECT_TRUE(got.empty());
}

// The grid queries' sort (sorted_ids.h): the list std::sort and std::unique give, for ids in a
// narrow range (the bitmap) and spread wide (the sort), one call after another on one thread
// (the bitmap must be left cleared), with repeats and without.
TEST(SpatialIndexTest, sort_unique_ids_matches_sort_and_unique) {
  std::mt19937 rng(20261126);
  for (int round = 0; round < 200; ++round) {
    const std::uint32_t base = std::uniform_int_distribution<std::uint32_t>(0, 1u << 20)(rng);
    const std::uint32_t span = round % 3 == 0 ? (1u << 22) : 1 + static_cast<std::uint32_t>(round) * 37;
    const std::size_t n = static_cast<std::size_t>(round % 5 == 0 ? 20 : 50 + 13 * round);
    std::uniform_int_distribution<std::uint32_t> pick(base, base + span - 1);
    std::vector<FaceId> ids;
    for (std::size_t i = 0; i < n; ++i) ids.push_back(FaceId(pick(rng)));
    std::vector<FaceId> want = ids;
    std::sort(want.begin(), want.end());
    want.erase(std::unique(want.begin(), want.end()), want.end());
    detail::sort_unique_ids(ids);
    ASSERT_EQ(ids, want) << "round " << round;
  }
}

// The packed per-cell lists (csr_fill.h) equal the ones filed item by item in order, for every
// thread count: few cells (a count per chunk and cell), many (by buckets of cells, a partial one
// last), items in no cell and in runs of cells.
TEST(SpatialIndexTest, fill_csr_lists_every_cell_in_item_order_for_every_thread_count) {
  const std::size_t saved = thread_count();
  std::mt19937 rng(20261128);
  for (const std::size_t cells :
       {std::size_t(5), std::size_t(3000), std::size_t(200003), std::size_t(5000011)}) {
    const std::size_t n = 100000;
    std::vector<std::uint32_t> first(n), count(n);
    std::uniform_int_distribution<std::uint32_t> cell(0, static_cast<std::uint32_t>(cells - 1)), runs(0, 3);
    for (std::size_t i = 0; i < n; ++i) {
      first[i] = cell(rng);
      count[i] = std::min<std::uint32_t>(runs(rng), static_cast<std::uint32_t>(cells - first[i]));
    }
    auto cells_of = [&](std::size_t i, auto&& visit) {
      for (std::uint32_t k = 0; k < count[i]; ++k) visit(std::size_t(first[i] + k));
    };
    std::vector<std::vector<std::uint32_t>> want(cells);
    for (std::size_t i = 0; i < n; ++i)
      cells_of(i, [&](std::size_t c) { want[c].push_back(static_cast<std::uint32_t>(i)); });
    for (const std::size_t threads : {1, 2, 5}) {
      set_thread_count(threads);
      std::vector<std::uint32_t> start, items;
      detail::fill_csr(n, cells, start, items, cells_of);
      auto check = [&](const char* how) {
        ASSERT_EQ(start.size(), cells + 1) << how << ", " << cells << " cells, " << threads << " threads";
        ASSERT_EQ(start[cells], items.size());
        for (std::size_t c = 0; c < cells; ++c)
          ASSERT_TRUE(std::equal(items.begin() + start[c], items.begin() + start[c + 1], want[c].begin(),
                                 want[c].end()))
              << how << ", cell " << c << " of " << cells << ", " << threads << " threads";
      };
      check("fill_csr");
      if (cells < 200000) continue;
      // The widest buckets, which fill_csr takes only above about 2^31 cells.
      start.clear();
      items.clear();
      detail::fill_csr_by_bucket(n, cells, 1 << 15, 16, start, items, cells_of);
      check("buckets of 65536 cells");
    }
  }
  set_thread_count(saved);
}

// The prefix sum's total past UINT32_MAX throws before any offset is put, whether one block's
// sum or only the blocks' total passes it; UINT32_MAX itself is a total.
TEST(SpatialIndexTest, exclusive_scan_throws_past_32_bit_offsets) {
  std::size_t puts = 0;
  auto put = [&puts](std::size_t, std::uint32_t) { ++puts; };
  EXPECT_THROW(detail::exclusive_scan(
                   3, [](std::size_t) { return 0x80000000u; }, put),
               Error);
  EXPECT_THROW(detail::exclusive_scan(
                   70000, [](std::size_t) { return 70000u; }, put),
               Error);
  EXPECT_THROW(detail::exclusive_scan(
                   (std::size_t(1) << 17) + 2,
                   [](std::size_t i) { return i % (std::size_t(1) << 16) == 0 ? 0xffffffffu : 0u; }, put),
               Error);
  EXPECT_EQ(puts, 0u);
  std::vector<std::uint32_t> at(2);
  EXPECT_EQ(detail::exclusive_scan(
                2, [](std::size_t i) { return i == 0 ? 0xfffffff0u : 0xfu; },
                [&](std::size_t i, std::uint32_t a) { at[i] = a; }),
            0xffffffffu);
  EXPECT_EQ(at, (std::vector<std::uint32_t>{0u, 0xfffffff0u}));
}

// The grid's serial copies run beside its passes over the faces: the same layout whether they
// run before every chunk, after every chunk or where the pool puts them, on 1, 2 and 5 threads.
TEST(SpatialIndexTest, build_lays_out_the_same_grid_whatever_runs_beside_its_passes) {
  const std::size_t saved = thread_count();
  SurfaceMesh mesh = test::make_tube(400, 200, 1.0f, 4.0f);  // 160000 faces: five chunks
  set_thread_count(1);
  const TriangleGrid one = TriangleGrid::build(mesh, mesh.positions());
  // Points on the surface, answered from the grid's own copies of the corners and positions.
  std::vector<glm::vec3> probes;
  for (std::size_t v = 0; v < mesh.positions().size(); v += 997) probes.push_back(mesh.positions()[v]);
  const std::vector<FaceId> want = one.query_points(probes);
  for (const auto order :
       {detail::BesideOrder::Shared, detail::BesideOrder::First, detail::BesideOrder::Last})
    for (const std::size_t threads : {1, 2, 5}) {
      set_thread_count(threads);
      const TriangleGrid grid = [&] {
        const detail::BesideOrderForTests in_order(order);
        return TriangleGrid::build(mesh, mesh.positions());
      }();
      EXPECT_EQ(grid.layout_hash(), one.layout_hash()) << int(order) << ", " << threads << " threads";
      EXPECT_EQ(grid.query_points(probes), want) << int(order) << ", " << threads << " threads";
    }
  set_thread_count(saved);
}

}  // namespace deepcut
