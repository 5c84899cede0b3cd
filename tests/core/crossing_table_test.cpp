// SPDX-License-Identifier: MIT
// The crossing table and needle merges the conforming insertions share (ops/common).
#include "ops/common/crossing_table.h"

#include <gtest/gtest.h>

#include <random>
#include <unordered_map>

#include "deepcut/core/mesh_editor.h"
#include "fixtures.h"

namespace deepcut::detail {
namespace {

using deepcut::MeshEditor;

struct Record {
  int value = -1;
};

TEST(EdgeKey, IsTheSameBothWaysAndDirectedKeyIsNot) {
  EXPECT_EQ(edge_key(VertexId(3), VertexId(7)), edge_key(VertexId(7), VertexId(3)));
  EXPECT_EQ(edge_key(VertexId(3), VertexId(7)), (std::uint64_t(3) << 32) | 7u);
  EXPECT_NE(directed_key(VertexId(3), VertexId(7)), directed_key(VertexId(7), VertexId(3)));
}

TEST(CrossingTable, FindsEachEdgeEitherWayAndMakesItOnce) {
  CrossingTable<Record> table;
  EXPECT_EQ(table.find(VertexId(1), VertexId(2)), nullptr);
  auto [r, made] = table.try_emplace(VertexId(2), VertexId(1));
  ASSERT_TRUE(made);
  EXPECT_EQ(r->value, -1);  // default-made: the caller fills it in
  r->value = 12;
  auto [again, made_again] = table.try_emplace(VertexId(1), VertexId(2));
  EXPECT_FALSE(made_again);
  EXPECT_EQ(again, r);
  ASSERT_NE(table.find(VertexId(1), VertexId(2)), nullptr);
  EXPECT_EQ(table.find(VertexId(1), VertexId(2))->value, 12);
  EXPECT_EQ(table.size(), 1u);
  EXPECT_EQ(table.key(0), edge_key(VertexId(1), VertexId(2)));
  EXPECT_EQ(table.find_key(table.key(0)), r);
  EXPECT_EQ(table.find_key(edge_key(VertexId(1), VertexId(3))), nullptr);
}

// Many random edges, with and without sizing up front: every lookup agrees with a std map,
// references made early stay valid as the table grows, and iteration is insertion order.
TEST(CrossingTable, AgreesWithAMapThroughGrowthAndKeepsRecordsInPlace) {
  for (std::size_t reserved : {std::size_t(0), std::size_t(5000)}) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> pick(0, 400);
    CrossingTable<Record> table;
    table.reserve(reserved);
    std::unordered_map<std::uint64_t, int> reference;
    std::vector<std::uint64_t> order;
    std::vector<const Record*> made_at;  // each record where it was made: records never move
    for (int i = 0; i < 20000; ++i) {
      const VertexId a(pick(rng)), b(pick(rng));
      if (a == b) continue;
      auto [r, made] = table.try_emplace(a, b);
      const auto [it, inserted] = reference.emplace(edge_key(a, b), i);
      ASSERT_EQ(made, inserted);
      if (made) {
        r->value = i;
        order.push_back(edge_key(a, b));
        made_at.push_back(r);
      }
      ASSERT_EQ(r->value, it->second);
    }
    ASSERT_EQ(table.size(), reference.size());
    for (std::size_t i = 0; i < table.size(); ++i) {
      EXPECT_EQ(&table[i], made_at[i]) << "record " << i << " moved";
      EXPECT_EQ(table.key(i), order[i]);
      EXPECT_EQ(table[i].value, reference.at(order[i]));
    }
    std::size_t n = 0;
    for (const Record& r : table) EXPECT_EQ(r.value, reference.at(order[n++]));
    EXPECT_EQ(n, table.size());
    const std::uint64_t k = order[order.size() / 2];
    const VertexId lo(static_cast<std::uint32_t>(k >> 32)), hi(static_cast<std::uint32_t>(k & 0xffffffffu));
    ASSERT_NE(table.find(hi, lo), nullptr);
    EXPECT_EQ(table.find(hi, lo)->value, reference.at(k));
  }
}

TEST(CrossingTable, ClearForgetsEveryEdge) {
  CrossingTable<Record> table;
  for (std::uint32_t i = 0; i < 100; ++i)
    table.try_emplace(VertexId(i), VertexId(i + 1)).first->value = int(i);
  table.clear();
  EXPECT_TRUE(table.empty());
  for (std::uint32_t i = 0; i < 100; ++i) EXPECT_EQ(table.find(VertexId(i), VertexId(i + 1)), nullptr);
  EXPECT_TRUE(table.try_emplace(VertexId(5), VertexId(6)).second);
  EXPECT_EQ(table.size(), 1u);
}

// Records are kept in blocks that a clear keeps: every record made after it (in the first block,
// which held written records, and past it) is default-made, as a new table's.
TEST(CrossingTable, RecordsMadeAfterAClearAreDefaultMade) {
  CrossingTable<Record> table;
  for (std::uint32_t i = 0; i < 200; ++i)
    table.try_emplace(VertexId(i), VertexId(i + 1)).first->value = int(i);
  table.clear();
  for (std::uint32_t i = 0; i < 300; ++i) {
    const auto [r, made] = table.try_emplace(VertexId(i + 1000), VertexId(i));
    ASSERT_TRUE(made);
    EXPECT_EQ(r->value, -1) << "record " << i;
  }
  EXPECT_EQ(table.size(), 300u);
  EXPECT_EQ(&table[0], table.find(VertexId(1000), VertexId(0)));
}

TEST(NeedleMerges, FollowLinksToTheLowestAndKeepTheFirstLink) {
  NeedleMerges merges;
  EXPECT_EQ(merges.merged(VertexId(9)), VertexId(9));
  merges.merge(VertexId(9), VertexId(5));
  merges.merge(VertexId(5), VertexId(2));
  merges.merge(VertexId(9), VertexId(7));  // 9 is linked already: ignored
  EXPECT_EQ(merges.merged(VertexId(9)), VertexId(2));
  EXPECT_EQ(merges.merged(VertexId(5)), VertexId(2));
  EXPECT_EQ(merges.merged(VertexId(7)), VertexId(7));
  EXPECT_EQ(merges.size(), 2u);
}

// The needle fan's two long edges split at one parameter round to one bind position: the two
// crossings become one vertex (the later to the earlier); distinct positions stay apart.
TEST(NeedleMerges, MergeCoincidentCrossingsOfANeedle) {
  SurfaceMesh mesh = test::make_needle_fan();
  const auto first_new = static_cast<std::uint32_t>(mesh.vertex_count());
  MeshEditor editor(mesh);
  // The middle face: X (0) with the two far corners one float step apart.
  const Triangle t = mesh.face(FaceId(1));
  VertexId x = t[0], p = t[1], q = t[2];
  for (int k = 0; k < 3; ++k)
    if (mesh.position(t[k]) == glm::vec3(0, 1, 0)) {
      x = t[k];
      p = t[(k + 1) % 3];
      q = t[(k + 2) % 3];
    }
  const VertexId a = editor.add_vertex_on_edge(x, p, 0.5f), b = editor.add_vertex_on_edge(x, q, 0.5f);
  ASSERT_GE(a.index, first_new);
  NeedleMerges merges;
  ASSERT_EQ(mesh.position(a), mesh.position(b));
  EXPECT_TRUE(merges.merge_if_coincident(mesh, b, a));
  EXPECT_EQ(merges.merged(b), a);
  EXPECT_FALSE(merges.merge_if_coincident(mesh, a, b));  // one vertex already
  const VertexId c = editor.add_vertex_on_edge(x, p, 0.25f);
  EXPECT_FALSE(merges.merge_if_coincident(mesh, a, c));
  EXPECT_EQ(merges.merged(c), c);
}

}  // namespace
}  // namespace deepcut::detail
