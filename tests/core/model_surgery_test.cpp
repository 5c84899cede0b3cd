// SPDX-License-Identifier: MIT
// Model surgery (ops/common): the one instance loop of the model-level operations, with
// copy-on-write of shared meshes, primitives added and removed, piece nodes and dropped
// instances, and the posed model kept in step.
#include "ops/common/model_surgery.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/parallel.h"
#include "fixtures.h"
#include "posed_checks.h"

namespace deepcut::detail {
namespace {

// Nodes: 0 "root" (scene root, parent of 1), 1 "a" and 2 "b" drawing mesh 0 (shared), 3 "c"
// drawing mesh 1 alone (a scene root); node 2 moved along x.
Model make_scene() {
  Model model;
  Mesh shared{"shared", {}, ""};
  Primitive prim;
  prim.mesh = test::make_tube(8, 2);
  shared.primitives.push_back(prim);
  Mesh own{"own", {}, ""};
  own.primitives.push_back(prim);
  own.primitives.push_back(prim);
  model.meshes = {shared, own};
  Node root, a, b, c;
  root.name = "root";
  root.children = {1};
  a.name = "a";
  a.mesh = 0;
  b.name = "b";
  b.mesh = 0;
  b.translation = {3.0f, 0.0f, 0.0f};
  c.name = "c";
  c.mesh = 1;
  model.nodes = {root, a, b, c};
  model.scenes = {{0, 2, 3}};
  return model;
}

void expect_posed_matches_rebuild(PosedModel& posed, const Model& model) {
  posed.prepare(model, -1, 0.0f);
  EXPECT_EQ(test::difference_from_fresh_build(posed, model), "");
}

TEST(ModelSurgery, VisitsEveryNodeDrawingAMeshWithItsPosedPrimitives) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  std::vector<int> nodes;
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    nodes.push_back(inst.node());
    EXPECT_EQ(inst.shared(), inst.mesh() == 0);
    for (std::size_t p = 0; p < inst.source().primitives.size(); ++p) {
      const PosedMesh* pm = inst.posed(static_cast<int>(p));
      EXPECT_NE(pm, nullptr);
      if (pm) {
        EXPECT_EQ(pm->posed.size(), inst.source().primitives[p].mesh.vertex_count());
      }
    }
    return false;
  });
  EXPECT_EQ(nodes, (std::vector<int>{1, 2, 3}));
}

TEST(ModelSurgery, AnEditedSharedMeshBecomesTheNodesOwnCopy) {
  Model model = make_scene();
  const Model before = model;
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() != 2) return false;
    Mesh& mesh = inst.edit();
    EXPECT_NE(&mesh, &inst.source());  // shared: a copy
    MeshEditor editor(mesh.primitives[0].mesh);
    editor.remove_face(FaceId(0));
    posed.follow(model, 2, 0, mesh.primitives[0].mesh, editor.log());
    return true;
  });
  ASSERT_EQ(model.meshes.size(), 3u);
  EXPECT_EQ(model.nodes[1].mesh, 0);
  EXPECT_EQ(model.nodes[2].mesh, 2);
  EXPECT_EQ(model.meshes[0].primitives[0].mesh.face_count(),
            before.meshes[0].primitives[0].mesh.face_count());
  EXPECT_EQ(model.meshes[2].primitives[0].mesh.face_count() + 1,
            before.meshes[0].primitives[0].mesh.face_count());
  EXPECT_EQ(posed.find(2, 0)->mesh, 2);
  expect_posed_matches_rebuild(posed, model);
}

TEST(ModelSurgery, ACopyNotReportedAsEditedIsDropped) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    inst.edit();
    return false;
  });
  EXPECT_EQ(model.meshes.size(), 2u);
  EXPECT_EQ(model.nodes[2].mesh, 0);
}

TEST(ModelSurgery, AnUnsharedMeshIsEditedInPlace) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() == 3) {
      EXPECT_EQ(&inst.edit(), &model.meshes[1]);
    }
    return inst.node() == 3;
  });
  EXPECT_EQ(model.meshes.size(), 2u);
  EXPECT_EQ(model.nodes[3].mesh, 1);
}

TEST(ModelSurgery, PrimitivesAddedAndErasedAreFollowedByThePosedModel) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() == 1) return false;
    inst.erase_primitive(0);
    Primitive extra;
    extra.mesh = test::make_tube(4, 1);
    inst.add_primitive(std::move(extra));
    return true;
  });
  // Node 2's shared mesh went to a copy; node 3's mesh was edited in place.
  ASSERT_EQ(model.meshes.size(), 3u);
  EXPECT_EQ(model.nodes[2].mesh, 2);
  EXPECT_EQ(model.meshes[2].primitives.size(), 1u);
  EXPECT_EQ(model.meshes[1].primitives.size(), 2u);
  EXPECT_EQ(model.meshes[0].primitives.size(), 1u);
  ASSERT_NE(posed.find(3, 1), nullptr);
  EXPECT_EQ(posed.find(3, 1)->posed.size(), model.meshes[1].primitives[1].mesh.vertex_count());
  expect_posed_matches_rebuild(posed, model);
}

TEST(ModelSurgery, DroppedInstancesDrawNothingAndTheLastUserEmptiesTheMesh) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() == 1 || inst.node() == 3) inst.drop();
    return true;
  });
  EXPECT_EQ(model.nodes[1].mesh, -1);
  EXPECT_EQ(model.nodes[1].skin, -1);
  EXPECT_EQ(model.meshes[0].primitives.size(), 1u);  // node 2 still draws it
  EXPECT_TRUE(model.meshes[1].primitives.empty());   // nobody draws it
  EXPECT_EQ(posed.find(1, 0), nullptr);
  EXPECT_EQ(posed.find(3, 0), nullptr);
  ModelSurgery surgery(model, posed);
  surgery.drop_instance(2);
  EXPECT_TRUE(model.meshes[0].primitives.empty());
  expect_posed_matches_rebuild(posed, model);
}

TEST(ModelSurgery, PrimitivesAddedAfterErasesAreIndexedWhereTheyLand) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() == 1) return false;
    // Erased from the back, as the drill erases swallowed primitives, then two walls appended.
    for (int p = static_cast<int>(inst.edit().primitives.size()); p-- > 0;) inst.erase_primitive(p);
    for (int k = 1; k <= 2; ++k) {
      Primitive wall;
      wall.mesh = test::make_tube(4 + k, 1);
      inst.add_primitive(std::move(wall));
    }
    return true;
  });
  ASSERT_EQ(model.meshes.size(), 3u);
  EXPECT_EQ(model.nodes[2].mesh, 2);  // the shared mesh's edited copy
  for (int node : {2, 3}) {
    const Mesh& mesh = model.meshes[static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(node)].mesh)];
    ASSERT_EQ(mesh.primitives.size(), 2u);
    for (int p = 0; p < 2; ++p) {
      ASSERT_NE(posed.find(node, p), nullptr);
      EXPECT_EQ(posed.find(node, p)->posed.size(), mesh.primitives[static_cast<std::size_t>(p)].mesh.vertex_count());
    }
  }
  EXPECT_EQ(model.meshes[0].primitives.size(), 1u);  // node 1 still draws the original
  expect_posed_matches_rebuild(posed, model);
}

TEST(ModelSurgery, AnInstanceLeftWithoutPrimitivesIsDroppedWithItsSkin) {
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  model.nodes[2].skin = 0;  // read by nobody here: the drop clears it
  model.nodes[3].skin = 0;
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() == 1) return false;
    for (int p = static_cast<int>(inst.edit().primitives.size()); p-- > 0;) inst.erase_primitive(p);
    if (inst.edit().primitives.empty()) inst.drop();
    return true;
  });
  EXPECT_EQ(model.meshes.size(), 2u);  // the shared mesh's copy was not kept
  for (int node : {2, 3}) {
    EXPECT_EQ(model.nodes[static_cast<std::size_t>(node)].mesh, -1);
    EXPECT_EQ(model.nodes[static_cast<std::size_t>(node)].skin, -1);
    EXPECT_EQ(posed.find(node, 0), nullptr);
  }
  EXPECT_EQ(model.meshes[0].primitives.size(), 1u);  // node 1 still draws it
  EXPECT_TRUE(model.meshes[1].primitives.empty());
  expect_posed_matches_rebuild(posed, model);
}

TEST(ModelSurgery, PiecesReplaceTheMeshAndAddNodesBesideTheInstance) {
  Model model = make_scene();
  model.nodes.push_back(model.nodes[1]);  // a node already named "a_piece1" would clash
  model.nodes.back().name = "a_piece1";
  model.nodes.back().mesh = -1;
  model.nodes[0].children.push_back(4);
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  std::vector<int> added;
  for_each_instance(model, posed, [&](InstanceEdit& inst) {
    if (inst.node() != 1 && inst.node() != 3) return false;
    Mesh piece0 = inst.source(), piece1 = inst.source();
    piece0.name = "p0";
    piece1.name = "p1";
    inst.replace_mesh(std::move(piece0));
    added.push_back(inst.add_piece_node(std::move(piece1),
                                        model.nodes[static_cast<std::size_t>(inst.node())].name + "_piece1"));
    return true;
  });
  // Node 1 shared mesh 0: its piece is a new mesh; node 3 owned mesh 1: replaced in place.
  ASSERT_EQ(added, (std::vector<int>{5, 6}));
  EXPECT_EQ(model.nodes[1].mesh, 2);
  EXPECT_EQ(model.meshes[2].name, "p0");
  EXPECT_EQ(model.nodes[5].mesh, 3);
  EXPECT_EQ(model.nodes[5].name, "a_piece1_2");
  EXPECT_EQ(model.nodes[3].mesh, 1);
  EXPECT_EQ(model.meshes[1].name, "p0");
  EXPECT_EQ(model.nodes[6].mesh, 4);
  EXPECT_EQ(model.nodes[6].name, "c_piece1");
  EXPECT_EQ(model.nodes[2].mesh, 0);  // the other user keeps the shared mesh
  // Piece nodes hang where their instance hangs: under node 0, or as a scene root.
  EXPECT_EQ(model.nodes[0].children, (std::vector<int>{1, 4, 5}));
  EXPECT_EQ(model.scenes[0], (std::vector<int>{0, 2, 3, 6}));
  EXPECT_TRUE(model.nodes[5].children.empty());
  EXPECT_EQ(posed.find(1, 0), nullptr);  // indexed anew by the next prepare
  expect_posed_matches_rebuild(posed, model);
}

TEST(ModelSurgery, ExtractKeepsOnlyTheGivenFacesAndTheirVertices) {
  const SurfaceMesh mesh = test::make_grid(2, 1);
  const SurfaceMesh part = extract(mesh, {FaceId(1), FaceId(0)});
  EXPECT_EQ(part.face_count(), 2u);
  EXPECT_EQ(part.vertex_count(), 4u);
  for (std::uint32_t f = 0; f < 2; ++f)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(part.position(part.face(FaceId(f))[k]), mesh.position(mesh.face(FaceId(f))[k]));
}

// Every byte of two meshes: faces, deleted marks and every attribute of every element kind.
void expect_same_bytes(const SurfaceMesh& a, const SurfaceMesh& b) {
  ASSERT_EQ(a.faces(), b.faces());
  ASSERT_EQ(a.face_count(), b.face_count());
  const std::pair<const AttributeSet*, const AttributeSet*> sets[] = {
      {&a.vertex_attrs(), &b.vertex_attrs()}, {&a.face_attrs(), &b.face_attrs()}, {&a.corner_attrs(), &b.corner_attrs()}};
  for (const auto& [x, y] : sets) {
    ASSERT_EQ(x->names(), y->names());
    ASSERT_EQ(x->size(), y->size());
    for (const std::string& name : x->names()) {
      const AttributeArrayBase* u = x->base(name);
      const AttributeArrayBase* v = y->base(name);
      ASSERT_EQ(u->element_bytes(), v->element_bytes()) << name;
      for (std::size_t i = 0; i < u->size(); ++i)
        ASSERT_EQ(std::memcmp(u->element_data(i), v->element_data(i), u->element_bytes()), 0) << name << " " << i;
    }
  }
}

TEST(ModelSurgery, ExtractDisjointGivesWhatExtractGivesForEveryList) {
  // A grid large enough for several parallel chunks, a face deleted, lists out of order.
  SurfaceMesh mesh = test::make_grid(420, 200);
  auto& flag = mesh.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  for (std::uint32_t f = 0; f < mesh.face_slots(); f += 7) flag[f] = 1;
  mesh.mark_deleted(FaceId(5));
  std::vector<std::vector<FaceId>> left(1), right(1);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const float x = mesh.position(t[0]).x + mesh.position(t[1]).x + mesh.position(t[2]).x;
    (x < 1.2f ? left[0] : right[0]).push_back(f);
  });
  left[0].push_back(FaceId(5));
  std::reverse(right[0].begin(), right[0].end());
  // The two halves share the vertices along the middle: extracted one by one.
  const std::vector<std::vector<FaceId>> shared = {left[0], right[0]};
  // Every third row alone: no vertex in two lists.
  std::vector<std::vector<FaceId>> rows(2);
  mesh.for_each_face([&](FaceId f, const Triangle&) {
    const std::uint32_t row = f.index / (2 * 420);
    if (row % 3 == 0) rows[row % 2].push_back(f);
  });
  rows.emplace_back();  // an empty list gives an empty mesh
  for (const auto& lists : {shared, rows}) {
    const std::vector<SurfaceMesh> out = extract_disjoint(mesh, lists);
    ASSERT_EQ(out.size(), lists.size());
    for (std::size_t i = 0; i < lists.size(); ++i) expect_same_bytes(out[i], extract(mesh, lists[i]));
  }
}

TEST(ModelSurgery, SplitDisjointGivesWhatExtractGivesWhicheverPieceKeepsTheArrays) {
  // Big enough for several copy chunks per stretch. Lists of whole row bands (one band leading,
  // so most of its elements stay put, another far behind) and of rows far apart and close
  // together (short reaches, copied in order); a face deleted, lists out of order.
  SurfaceMesh mesh = test::make_grid(420, 200);
  auto& flag = mesh.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  for (std::uint32_t f = 0; f < mesh.face_slots(); f += 7) flag[f] = 1;
  // Arrays of types the library does not make itself, with distinct values.
  auto& ids = mesh.vertex_attrs().add<std::uint32_t>("v:test_id");
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) ids[v] = 7u * v + 1u;
  auto& tags = mesh.corner_attrs().add<glm::uvec2>("c:test_tag");
  for (std::uint32_t c = 0; c < 3 * mesh.face_slots(); ++c) tags[c] = glm::uvec2(c, 3u * c + 2u);
  mesh.mark_deleted(FaceId(5));
  const std::uint32_t row_faces = 2 * 420;
  auto rows = [&](auto wanted) {
    std::vector<FaceId> out;
    mesh.for_each_face([&](FaceId f, const Triangle&) {
      if (wanted(f.index / row_faces)) out.push_back(f);
    });
    return out;
  };
  std::vector<FaceId> top = rows([](std::uint32_t r) { return r >= 61; });
  std::reverse(top.begin(), top.end());
  const std::vector<std::vector<std::vector<FaceId>>> cases = {
      {rows([](std::uint32_t r) { return r < 60; }), top},
      {rows([](std::uint32_t r) { return r < 150; }), rows([](std::uint32_t r) { return r > 151; })},
      {rows([](std::uint32_t r) { return r % 3 == 0; }), rows([](std::uint32_t r) { return r % 3 == 2 && r > 100; }), {}},
  };
  const std::size_t saved = thread_count();
  for (std::size_t threads : {1u, 3u})
    for (const auto& lists : cases) {
      set_thread_count(threads);
      SurfaceMesh taken = mesh;
      const std::vector<SurfaceMesh> out = split_disjoint(std::move(taken), lists);
      set_thread_count(saved);
      ASSERT_EQ(out.size(), lists.size());
      for (std::size_t i = 0; i < lists.size(); ++i) expect_same_bytes(out[i], extract(mesh, lists[i]));
    }
}

TEST(ModelSurgery, ACutsVertexSidesSplitItsMeshAsItsPiecesFacesDo) {
  // The cut's vertex sides agree with the faces of its pieces (a vertex no piece uses: 0, or the
  // side the cut dropped), and the pieces split by them are the pieces split by their faces.
  CactusOptions cactus;
  cactus.target_triangles = 60000;
  const SurfaceMesh input = make_cactus(cactus).meshes[0].primitives[0].mesh;
  const BoundingBox box = input.bounds();
  const Plane plane{0.5f * (box.min + box.max), glm::vec3(0.1f, 1.0f, 0.05f)};
  for (CutKeep keep : {CutKeep::Both, CutKeep::Positive, CutKeep::Negative}) {
    SurfaceMesh mesh = input;
    CutOptions options;
    options.keep = keep;
    const CutResult r = cut_mesh(mesh, mesh.positions(), plane, options);
    ASSERT_EQ(r.status, OpStatus::Ok);
    ASSERT_EQ(CutSides::of(r).size(), mesh.vertex_count());
    std::vector<int> side_of(mesh.vertex_count(), 0);
    for (std::size_t p = 0; p < r.pieces.size(); ++p)
      for (FaceId f : r.pieces[p])
        for (VertexId v : mesh.face(f)) side_of[v.index] = r.piece_sides[p];
    const int dropped = keep == CutKeep::Positive ? -1 : keep == CutKeep::Negative ? 1 : 0;
    for (std::size_t v = 0; v < side_of.size(); ++v) {
      const bool dropped_side = side_of[v] == 0 && CutSides::of(r)[v] == dropped;
      EXPECT_TRUE(dropped_side || CutSides::of(r)[v] == side_of[v]) << v;
    }
    const PieceSides sides{&r.piece_sides, &CutSides::of(r)};
    SurfaceMesh a = mesh, b = mesh;
    const std::vector<SurfaceMesh> by_sides = split_disjoint(std::move(a), r.pieces, sides);
    const std::vector<SurfaceMesh> by_faces = split_disjoint(std::move(b), r.pieces);
    ASSERT_EQ(by_sides.size(), by_faces.size());
    for (std::size_t i = 0; i < by_sides.size(); ++i) expect_same_bytes(by_sides[i], by_faces[i]);
  }
  // Not handed out for caps, or for a mesh with deleted faces (a vertex only they use has a sign).
  SurfaceMesh mesh = input;
  CutOptions capped;
  capped.cap = true;
  EXPECT_TRUE(CutSides::of(cut_mesh(mesh, mesh.positions(), plane, capped)).empty());
  mesh = input;
  mesh.mark_deleted(FaceId(0));
  EXPECT_TRUE(CutSides::of(cut_mesh(mesh, mesh.positions(), plane)).empty());
}

// A generated cactus of about `triangles` triangles cut across its middle by a slanted plane
// (both pieces kept, no cap): the mesh after the cut and the cut's result, asserted to have
// gone through in two pieces (call it in ASSERT_NO_FATAL_FAILURE).
struct CactusCut {
  SurfaceMesh mesh;
  CutResult result;
};
void cut_cactus(std::size_t triangles, CactusCut& out) {
  CactusOptions cactus;
  cactus.target_triangles = triangles;
  out.mesh = make_cactus(cactus).meshes[0].primitives[0].mesh;
  const BoundingBox box = out.mesh.bounds();
  const Plane plane{0.5f * (box.min + box.max), glm::vec3(0.1f, 1.0f, 0.05f)};
  out.result = cut_mesh(out.mesh, out.mesh.positions(), plane, CutOptions{});
  ASSERT_EQ(out.result.status, OpStatus::Ok);
  ASSERT_EQ(out.result.pieces.size(), 2u);
}

TEST(ModelSurgery, VertexSidesThatBreakTheFacesFallBackToSplittingByFaces) {
  // Sides that break the cut's promise (a used vertex with side 0, another on the other side)
  // are noticed: the pieces are those split by their faces, not renumbered through ranks that
  // were never written.
  CactusCut cut;
  ASSERT_NO_FATAL_FAILURE(cut_cactus(20000, cut));
  SurfaceMesh& mesh = cut.mesh;
  const CutResult& r = cut.result;
  for (int broken_side : {0, 2}) {
    std::vector<std::int8_t> sides_of = CutSides::of(r);
    const VertexId v = mesh.face(r.pieces[0][r.pieces[0].size() / 2])[1];
    sides_of[v.index] = broken_side == 0 ? std::int8_t(0) : std::int8_t(-sides_of[v.index]);
    const PieceSides sides{&r.piece_sides, &sides_of};
    SurfaceMesh a = mesh, b = mesh;
    const std::vector<SurfaceMesh> by_sides = split_disjoint(std::move(a), r.pieces, sides);
    const std::vector<SurfaceMesh> by_faces = split_disjoint(std::move(b), r.pieces);
    ASSERT_EQ(by_sides.size(), by_faces.size());
    for (std::size_t i = 0; i < by_sides.size(); ++i) expect_same_bytes(by_sides[i], by_faces[i]);
  }
}

TEST(ModelSurgery, VertexSidesWithListsOutOfOrderSplitAsTheSortedLists) {
  // Lists checked and copied in one pass only when each is live and increasing: a list out of
  // order (within a chunk of the pass or across two), or naming a face twice, is sorted first,
  // and the pieces are those of the cut's own lists.
  CactusCut cut;  // lists longer than one chunk (65536 faces) of the pass
  ASSERT_NO_FATAL_FAILURE(cut_cactus(200000, cut));
  SurfaceMesh& mesh = cut.mesh;
  const CutResult& r = cut.result;
  ASSERT_GT(r.pieces[1].size(), 65537u);
  const PieceSides sides{&r.piece_sides, &CutSides::of(r)};
  SurfaceMesh b = mesh;
  const std::vector<SurfaceMesh> by_faces = split_disjoint(std::move(b), r.pieces);
  for (int change = 0; change < 4; ++change) {
    std::vector<std::vector<FaceId>> lists = r.pieces;
    if (change == 0) std::reverse(lists[0].begin(), lists[0].end());
    if (change == 1) std::swap(lists[1][65535], lists[1][65536]);  // across two chunks
    if (change == 2) std::swap(lists[1][10], lists[1][11]);        // within one
    if (change == 3) lists[1].insert(lists[1].begin() + 65536, lists[1][65535]);
    SurfaceMesh a = mesh;
    const std::vector<SurfaceMesh> by_sides = split_disjoint(std::move(a), lists, sides);
    ASSERT_EQ(by_sides.size(), by_faces.size()) << change;
    for (std::size_t i = 0; i < by_sides.size(); ++i) expect_same_bytes(by_sides[i], by_faces[i]);
  }
}

TEST(ModelSurgery, VertexSidesWithDeletedFacesInTheListsKeepTheVerticesOnTheirSide) {
  // A list naming deleted faces fails the split's one-pass check; made live and increasing, it is
  // split by the vertex sides all the same, which keep a vertex only deleted faces used (marking by
  // the live faces would drop it): the pieces of the lists without those faces.
  CactusCut cut;
  ASSERT_NO_FATAL_FAILURE(cut_cactus(20000, cut));
  SurfaceMesh& mesh = cut.mesh;
  const CutResult& r = cut.result;
  const std::vector<std::int8_t>& side = CutSides::of(r);
  const PieceSides sides{&r.piece_sides, &side};
  // Every face of list 1 around one of its vertices deleted (still named by the list).
  const std::uint32_t v = mesh.face(r.pieces[1][r.pieces[1].size() / 2])[0].index;
  std::vector<std::vector<FaceId>> live = r.pieces;
  live[1].clear();
  for (FaceId f : r.pieces[1]) {
    const Triangle& t = mesh.face(f);
    if (t[0].index == v || t[1].index == v || t[2].index == v)
      mesh.mark_deleted(f);
    else
      live[1].push_back(f);
  }
  ASSERT_LT(live[1].size(), r.pieces[1].size());
  SurfaceMesh a = mesh, b = mesh;
  const std::vector<SurfaceMesh> with_deleted = split_disjoint(std::move(a), r.pieces, sides);
  const std::vector<SurfaceMesh> live_only = split_disjoint(std::move(b), live, sides);
  ASSERT_EQ(with_deleted.size(), 2u);
  ASSERT_EQ(live_only.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) expect_same_bytes(with_deleted[i], live_only[i]);
  const auto on_side = static_cast<std::size_t>(
      std::count(side.begin(), side.end(), static_cast<std::int8_t>(r.piece_sides[1])));
  EXPECT_EQ(with_deleted[1].vertex_count(), on_side);
}

TEST(ModelSurgery, ACutKeepsTheGridsOfTheInstancesItMisses) {
  // The instances a model cut cuts leave the posed model (followed without their grids); those
  // the plane misses keep their grids, and the posed model then matches a fresh build.
  Model model = make_scene();
  PosedModel posed = PosedModel::build(model, -1, 0.0f);
  const Plane plane{{3.05f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};  // through node b alone
  ASSERT_EQ(cut_model(model, posed, plane, CutOptions{}, -1, 0.0f).status, OpStatus::Ok);
  for (const auto& [node, primitive] : {std::pair{1, 0}, {3, 0}, {3, 1}}) {
    const PosedMesh* inst = posed.find(node, primitive);
    ASSERT_NE(inst, nullptr);
    EXPECT_FALSE(inst->gridless);
    EXPECT_EQ(inst->grid.face_count(), test::make_tube(8, 2).face_count());
  }
  EXPECT_EQ(posed.find(2, 0), nullptr);
  expect_posed_matches_rebuild(posed, model);
}

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(ModelSurgery, AModelCutWritesTheSameBytesWhateverTheThreadCount) {
  // Big enough for several parallel chunks in posing, classification and piece extraction.
  CactusOptions cactus;
  cactus.target_triangles = 160000;
  const Model input = make_cactus(cactus);
  const BoundingBox box = input.meshes[0].primitives[0].mesh.bounds();
  const std::string dir = std::filesystem::temp_directory_path().string();
  const std::size_t saved = thread_count();
  for (bool cap : {false, true}) {
    Operation op;
    CutOperation cut;
    cut.plane = {0.5f * (box.min + box.max), glm::vec3(0.1f, 1.0f, 0.05f)};
    cut.options.cap = cap;
    cut.options.split_components = cap;
    op.params = cut;
    op.animation = 0;
    op.time = 0.7f;
    std::vector<std::vector<char>> written;
    for (std::size_t threads : {1u, 2u, 5u}) {
      set_thread_count(threads);
      Model model = input;
      ASSERT_EQ(apply_operation(model, op).status, OpStatus::Ok);
      const std::string path = dir + "/deepcut_model_cut_threads_" + std::to_string(threads) + ".glb";
      write_gltf(model, path);
      written.push_back(file_bytes(path));
      std::remove(path.c_str());
    }
    set_thread_count(saved);
    ASSERT_FALSE(written[0].empty());
    for (std::size_t i = 1; i < written.size(); ++i) EXPECT_TRUE(written[i] == written[0]) << "cap " << cap << ", run " << i;
  }
}

TEST(ModelSurgery, CutSurfaceMaterialIsAddedOnce) {
  Model model = make_scene();
  const int m = cut_surface_material(model);
  EXPECT_EQ(model.materials[static_cast<std::size_t>(m)].name, "Cut surface");
  EXPECT_EQ(cut_surface_material(model), m);
  EXPECT_EQ(model.materials.size(), 1u);
}

}  // namespace
}  // namespace deepcut::detail
