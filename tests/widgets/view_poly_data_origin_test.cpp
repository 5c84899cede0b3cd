// SPDX-License-Identifier: MIT
// ViewPolyData of a cut's piece built through the piece's origin (ModelChange::origins: how its
// corners share points taken from the data drawn for the primitive it was cut out of) equals a
// fresh build of the piece: at rest and skinned, with uv seams, corner normals and morph targets,
// and from source data whose points were renumbered by earlier steps. Headless: VTK data only.

#include <gtest/gtest.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/model_undo.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/widgets/view_poly_data.h"
#include "fixtures.h"
#include "view_checks.h"

namespace deepcut {
namespace {

/// The grid (uv seam down its middle column) as a one-node model, standing up in the xz plane.
Model grid_model(int nx, int ny) {
  Model model;
  Primitive prim;
  prim.mesh = test::make_grid(nx, ny);
  for (auto& p : prim.mesh.vertex_attrs().get<glm::vec3>(attr::kPosition).data()) p = glm::vec3(p.x, 0.0f, p.y);
  Mesh mesh;
  mesh.primitives.push_back(std::move(prim));
  model.meshes.push_back(std::move(mesh));
  Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  model.scenes.push_back({0});
  model.default_scene = 0;
  return model;
}

/// The drawn data of one instance at one pose: its posed positions and corner normals.
struct Drawn {
  const SurfaceMesh* mesh = nullptr;
  std::vector<glm::vec3> positions, normals;
};

Drawn drawn(const Model& model, const PosedModel& posed, int node, int mesh, int primitive) {
  Drawn out;
  out.mesh = &model.meshes[static_cast<std::size_t>(mesh)].primitives[static_cast<std::size_t>(primitive)].mesh;
  const PosedMesh* pose = posed.find(node, primitive);
  EXPECT_NE(pose, nullptr);
  if (!pose) return out;
  out.positions = pose->posed;
  out.normals = pose->corner_normals(*out.mesh);
  return out;
}

/// The connectivity `view` draws, as values.
std::vector<vtkTypeInt64> connectivity_of(const ViewPolyData& view) {
  vtkTypeInt64Array* a = view.poly()->GetPolys()->GetConnectivityArray64();
  return std::vector<vtkTypeInt64>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
}

/// `view` (drawing `d`) follows a step that deletes every third face, then one that brings them
/// back: its points are then numbered otherwise than a fresh build's.
void renumber_points(ViewPolyData& view, const Drawn& d, const std::string& what) {
  SurfaceMesh fewer = *d.mesh;
  MeshEditor editor(fewer);
  for (std::uint32_t f = 0; f < fewer.face_slots(); f += 3)
    if (!fewer.is_deleted(FaceId(f))) editor.remove_face(FaceId(f));
  PrimitiveChange change;
  ASSERT_TRUE(diff_meshes(*d.mesh, fewer, change));
  view.update(fewer, d.positions, &d.normals, change);
  expect_rebuilt(view, fewer, d.positions, &d.normals, what + " (faces deleted)");
  ASSERT_TRUE(diff_meshes(fewer, *d.mesh, change));
  view.update(*d.mesh, d.positions, &d.normals, change);
  expect_rebuilt(view, *d.mesh, d.positions, &d.normals, what);
}

/// A cut of a model under an undo record (as the studio's session does, so the cut says where
/// its pieces came from): the model before and after, and the pieces' origins.
struct Cut {
  Model before, after;
  std::vector<std::shared_ptr<const PrimitiveOrigin>> origins;
};

void cut(Cut& out, Model model, const Plane& plane, int animation, float time) {
  out.before = model;
  Operation op;
  op.params = CutOperation{};
  std::get<CutOperation>(op.params).plane = plane;
  op.animation = animation;
  op.time = time;
  PosedModel posed;
  OperationResult result;
  {
    ModelRecorder recorder(model);
    result = apply_operation(model, op, posed);
    recorder.finish();
  }
  ASSERT_EQ(result.status, OpStatus::Ok);
  out.origins = std::get<ModelCutResult>(result.result).origins;
  ASSERT_FALSE(out.origins.empty());
  out.after = std::move(model);
}

/// What a check does with a piece's copied data before its first update.
enum class Then {
  update,   // the update builds the corner lists first
  prepare,  // `prepare_updates` (the studio's idle work) first
  pose,     // a new pose (`set_positions`, lists not built), checked, then the update
};

/// The copied data of one piece (`origin`) of `c`, from the source's data (renumbered by two
/// steps first with `renumber`), checked against a fresh build. The data must come from copying,
/// with the corner lists left for later.
std::unique_ptr<ViewPolyData> copy_piece(const Cut& c, const PrimitiveOrigin& origin,
                                         const PosedModel& posed_before, const PosedModel& posed_after,
                                         bool renumber, Drawn& piece) {
  const Drawn source =
      drawn(c.before, posed_before, origin.node_before, origin.mesh_before, origin.primitive_before);
  piece = drawn(c.after, posed_after, origin.node, origin.mesh, origin.primitive);
  EXPECT_TRUE(source.mesh && piece.mesh);
  if (!source.mesh || !piece.mesh) return nullptr;
  EXPECT_EQ(origin.faces.size(), piece.mesh->face_slots());
  EXPECT_EQ(origin.vertices.size(), piece.mesh->vertex_count());
  ViewPolyData source_view(*source.mesh, source.positions, &source.normals);
  if (renumber) renumber_points(source_view, source, "the source renumbered");
  auto copied =
      std::make_unique<ViewPolyData>(*piece.mesh, piece.positions, &piece.normals, source_view, origin);
  // (without corner points, one point per vertex slot: nothing to copy, nothing left for later)
  EXPECT_EQ(copied->copied(), copied->corner_points()) << "a full build instead of a copy";
  EXPECT_EQ(copied->updates_prepared(), !copied->corner_points()) << "corner lists built by the copy";
  expect_rebuilt(*copied, *piece.mesh, piece.positions, &piece.normals,
                 "piece of node " + std::to_string(origin.node));
  return copied;
}

/// Cuts `model` by `plane` at (`animation`, `time`), then checks every piece's data built through
/// its origin against a fresh build, and after `then` and steps that delete faces and bring them
/// back. With `renumber` the source's data first follows such steps, so its points are numbered
/// otherwise than a fresh build's.
void check_pieces(Model model, const Plane& plane, int animation, float time, bool renumber,
                  const std::string& what, Then then = Then::update) {
  SCOPED_TRACE(what);
  Cut c;
  cut(c, std::move(model), plane, animation, time);
  const PosedModel posed_before = PosedModel::build(c.before, animation, time, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(c.after, animation, time, PoseDetail::Positions);
  // Another pose: the next frame of the animation (at rest: the same).
  const PosedModel posed_next = PosedModel::build(c.after, animation, time + 0.5f, PoseDetail::Positions);
  for (const auto& origin : c.origins) {
    Drawn piece;
    const std::unique_ptr<ViewPolyData> copied =
        copy_piece(c, *origin, posed_before, posed_after, renumber, piece);
    if (!copied) continue;
    const std::string name = "piece of node " + std::to_string(origin->node);
    if (then == Then::prepare) {
      copied->prepare_updates();
      EXPECT_TRUE(copied->updates_prepared());
      expect_rebuilt(*copied, *piece.mesh, piece.positions, &piece.normals, name + ", prepared");
    } else if (then == Then::pose) {
      piece = drawn(c.after, posed_next, origin->node, origin->mesh, origin->primitive);
      copied->set_positions(piece.positions, &piece.normals);
      EXPECT_EQ(copied->updates_prepared(), !copied->corner_points());
      expect_rebuilt(*copied, *piece.mesh, piece.positions, &piece.normals, name + ", posed again");
    }
    // Its first update builds the corner lists the copy left out (unless prepared).
    renumber_points(*copied, piece, name + ", then updated");
    EXPECT_TRUE(copied->updates_prepared());
  }
}

Plane plane_through(const glm::vec3& point, const glm::vec3& normal) {
  Plane plane;
  plane.point = point;
  plane.normal = normal;
  return plane;
}

TEST(ViewPolyDataOriginTest, uv_seams_at_rest) {
  const Plane plane = plane_through({0.37f, 0.0f, 0.41f}, {0.3f, 0.0f, 1.0f});
  check_pieces(grid_model(12, 9), plane, -1, 0.0f, false, "fresh source");
  check_pieces(grid_model(12, 9), plane, -1, 0.0f, true, "renumbered source");
}

TEST(ViewPolyDataOriginTest, skinned_with_corner_normals) {
  const Plane plane = plane_through({0.0f, 1.3f, 0.0f}, {0.15f, 1.0f, 0.05f});
  check_pieces(test::make_skinned_tube_model(), plane, -1, 0.0f, false, "at rest");
  check_pieces(test::make_skinned_tube_model(), plane, 0, 0.5f, true, "bent");
}

TEST(ViewPolyDataOriginTest, morph_targets_skinned) {
  const Plane plane = plane_through({0.0f, 1.8f, 0.0f}, {-0.1f, 1.0f, 0.2f});
  check_pieces(test::make_morph_tube_model(), plane, -1, 0.0f, false, "at rest");
  check_pieces(test::make_morph_tube_model(), plane, 0, 1.0f, true, "bent and morphed");
}

TEST(ViewPolyDataOriginTest, prepared_then_updated) {
  const Plane plane = plane_through({0.0f, 1.8f, 0.0f}, {-0.1f, 1.0f, 0.2f});
  check_pieces(test::make_morph_tube_model(), plane, 0, 0.5f, true, "bent and morphed", Then::prepare);
  check_pieces(grid_model(12, 9), plane_through({0.37f, 0.0f, 0.41f}, {0.3f, 0.0f, 1.0f}), -1, 0.0f, false,
               "uv seams", Then::prepare);
}

TEST(ViewPolyDataOriginTest, posed_again_before_the_lists) {
  const Plane plane = plane_through({0.0f, 1.8f, 0.0f}, {-0.1f, 1.0f, 0.2f});
  check_pieces(test::make_morph_tube_model(), plane, 0, 0.5f, false, "bent and morphed", Then::pose);
  check_pieces(test::make_morph_tube_model(), plane, 0, 1.0f, true, "renumbered source", Then::pose);
}

// A live face whose three corners are one vertex drawn alike (a degenerate face the reader
// keeps, or three coincident vertices welded) names one point three times, as a deleted face's
// cell does. A piece copied with one keeps it live: a step that removes the vertex's other faces
// leaves the point to it (not compacted away under it).
TEST(ViewPolyDataOriginTest, a_face_collapsed_to_one_vertex_stays_drawn) {
  Model model = grid_model(12, 9);
  SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  const VertexId v(0);  // the corner (0, 0): its two faces' corners draw alike
  const FaceId collapsed = mesh.add_face(v, v, v);
  auto& uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0).data();
  auto& normal = mesh.corner_attrs().get<glm::vec3>(attr::kNormal).data();
  for (int k = 0; k < 3; ++k) {
    uv[SurfaceMesh::corner(collapsed, k)] = uv[SurfaceMesh::corner(FaceId(0), 0)];
    normal[SurfaceMesh::corner(collapsed, k)] = normal[SurfaceMesh::corner(FaceId(0), 0)];
  }
  Cut c;
  cut(c, std::move(model), plane_through({0.37f, 0.0f, 0.41f}, {0.3f, 0.0f, 1.0f}), -1, 0.0f);
  const PosedModel posed_before = PosedModel::build(c.before, -1, 0.0f, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(c.after, -1, 0.0f, PoseDetail::Positions);
  bool found = false;
  for (const auto& origin : c.origins) {
    Drawn piece;
    const std::unique_ptr<ViewPolyData> copied =
        copy_piece(c, *origin, posed_before, posed_after, false, piece);
    ASSERT_TRUE(copied);
    const auto at = std::find(origin->vertices.begin(), origin->vertices.end(), v.index);
    if (at == origin->vertices.end()) continue;
    const VertexId w(static_cast<std::uint32_t>(at - origin->vertices.begin()));
    SurfaceMesh fewer = *piece.mesh;
    MeshEditor editor(fewer);
    for (std::uint32_t f = 0; f < fewer.face_slots(); ++f) {
      const Triangle& t = fewer.face(FaceId(f));
      if (fewer.is_deleted(FaceId(f))) continue;
      if (t[0] == w && t[1] == w && t[2] == w) {
        found = true;
      } else if (t[0] == w || t[1] == w || t[2] == w) {
        editor.remove_face(FaceId(f));
      }
    }
    PrimitiveChange change;
    ASSERT_TRUE(diff_meshes(*piece.mesh, fewer, change));
    copied->update(fewer, piece.positions, &piece.normals, change);
    expect_rebuilt(*copied, fewer, piece.positions, &piece.normals, "the vertex's other faces removed");
  }
  EXPECT_TRUE(found) << "no piece kept the collapsed face";
}

// The chunked passes of the copy (more than two chunks of faces) give the same data whatever the
// thread count, equal to a fresh build, and so do the steps after it.
TEST(ViewPolyDataOriginTest, chunked_copy_is_the_same_whatever_the_thread_count) {
  Cut c;
  cut(c, grid_model(160, 120), plane_through({0.1f, 0.0f, 0.1f}, {0.3f, 0.0f, 1.0f}), -1, 0.0f);
  const PosedModel posed_before = PosedModel::build(c.before, -1, 0.0f, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(c.after, -1, 0.0f, PoseDetail::Positions);
  ASSERT_GT(c.before.meshes[0].primitives[0].mesh.face_slots(), 2u * 16384u);
  auto connectivity = [](const ViewPolyData& view) {
    vtkTypeInt64Array* a = view.poly()->GetPolys()->GetConnectivityArray64();
    return std::vector<vtkTypeInt64>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
  };
  const std::size_t saved = thread_count();
  std::vector<std::vector<vtkTypeInt64>> first;  // per piece and stage, with one thread
  for (std::size_t threads : {1u, 2u, 3u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    set_thread_count(threads);
    std::size_t i = 0;
    for (const auto& origin : c.origins) {
      Drawn piece;
      const std::unique_ptr<ViewPolyData> copied =
          copy_piece(c, *origin, posed_before, posed_after, true, piece);
      ASSERT_TRUE(copied);
      if (piece.mesh->face_slots() <= 2u * 16384u) continue;
      std::vector<vtkTypeInt64> got = connectivity(*copied);
      renumber_points(*copied, piece, "updated");
      for (auto& stage : {got, connectivity(*copied)}) {
        if (threads == 1) first.push_back(stage);
        ASSERT_LT(i, first.size());
        EXPECT_TRUE(stage == first[i++]) << "connectivity differs from one thread's";
      }
    }
    EXPECT_GE(i, 2u) << "no piece with more than two chunks of faces";
  }
  set_thread_count(saved);
}

/// The positions of `mesh`'s vertices (at rest, unposed).
const std::vector<glm::vec3>& rest(const SurfaceMesh& mesh) {
  return mesh.vertex_attrs().get<glm::vec3>(attr::kPosition).data();
}

/// `mesh` with every face but each `keep`-th deleted (its slots stay: as many cells, few points).
SurfaceMesh sparse_faces(const SurfaceMesh& mesh, std::uint32_t keep) {
  SurfaceMesh fewer = mesh;
  MeshEditor editor(fewer);
  for (std::uint32_t f = 0; f < fewer.face_slots(); ++f)
    if (f % keep != 0 && !fewer.is_deleted(FaceId(f))) editor.remove_face(FaceId(f));
  return fewer;
}

/// The cells' raw offsets (slots + 1) and face ids (slots) are the identity, and the point
/// arrays are those of a fresh build, in its order (what the VTK data's readers index by).
void expect_raw_like_fresh(const ViewPolyData& got, const SurfaceMesh& mesh) {
  const std::size_t slots = mesh.face_slots();
  vtkTypeInt64Array* offsets = got.poly()->GetPolys()->GetOffsetsArray64();
  auto* face_ids = vtkIdTypeArray::SafeDownCast(got.poly()->GetCellData()->GetArray("face_id"));
  ASSERT_TRUE(offsets && face_ids);
  ASSERT_EQ(offsets->GetNumberOfValues(), static_cast<vtkIdType>(slots + 1));
  ASSERT_EQ(face_ids->GetNumberOfValues(), static_cast<vtkIdType>(slots));
  for (std::size_t f = 0; f <= slots; ++f) ASSERT_EQ(offsets->GetValue(f), vtkTypeInt64(3 * f)) << "offset " << f;
  for (std::size_t f = 0; f < slots; ++f) ASSERT_EQ(face_ids->GetValue(f), vtkIdType(f)) << "face id " << f;
  const ViewPolyData fresh(mesh, rest(mesh));
  auto names = [](vtkDataSetAttributes* data) {
    std::vector<std::string> out;
    for (int i = 0; i < data->GetNumberOfArrays(); ++i) out.emplace_back(data->GetArrayName(i));
    return out;
  };
  EXPECT_EQ(names(got.poly()->GetPointData()), names(fresh.poly()->GetPointData()));
  EXPECT_EQ(names(got.poly()->GetCellData()), names(fresh.poly()->GetCellData()));
}

/// Gives `view` colour arrays, as the studio's inspectors do (point and cell "colors").
void colour(ViewPolyData& view) {
  vtkNew<vtkUnsignedCharArray> points, cells;
  points->SetName("colors");
  points->SetNumberOfComponents(3);
  points->SetNumberOfTuples(view.poly()->GetNumberOfPoints());
  points->FillValue(7);
  cells->SetName("colors");
  cells->SetNumberOfComponents(3);
  cells->SetNumberOfTuples(view.poly()->GetNumberOfCells());
  cells->FillValue(9);
  view.poly()->GetPointData()->AddArray(points);
  view.poly()->GetCellData()->AddArray(cells);
}

// A piece's copying build that takes a spare's arrays (more cells, fewer points, fewer cells
// within its room, prepared lists, colours) equals a fresh build, raw arrays included, and so do
// its steps after; the spare is left without data, the source unchanged; a spare too small is
// left alone. The same connectivity whatever the thread count, the spare spanning many chunks.
TEST(ViewPolyDataOriginTest, a_piece_taking_a_spare_equals_a_fresh_build) {
  Cut c;
  cut(c, grid_model(160, 120), plane_through({0.1f, 0.0f, 0.1f}, {0.3f, 0.0f, 1.0f}), -1, 0.0f);
  const PosedModel posed_before = PosedModel::build(c.before, -1, 0.0f, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(c.after, -1, 0.0f, PoseDetail::Positions);
  const SurfaceMesh& whole = c.before.meshes[0].primitives[0].mesh;
  const SurfaceMesh sparse = sparse_faces(whole, 50);
  enum Kind { bigger, fewer_points, fewer_cells, prepared, coloured, too_small };
  const std::size_t saved = thread_count();
  std::vector<std::vector<vtkTypeInt64>> first;  // per piece and kind, with one thread
  for (std::size_t threads : {1u, 2u, 3u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    set_thread_count(threads);
    std::size_t i = 0;
    for (const auto& origin : c.origins) {
      const Drawn source =
          drawn(c.before, posed_before, origin->node_before, origin->mesh_before, origin->primitive_before);
      const Drawn piece = drawn(c.after, posed_after, origin->node, origin->mesh, origin->primitive);
      ASSERT_TRUE(source.mesh && piece.mesh);
      const std::size_t slots = piece.mesh->face_slots();
      if (slots < 4000u) continue;  // (the smaller spare's room needs a build's slack)
      // A grid of a little fewer faces than the piece: its room (with a build's slack) holds it.
      const SurfaceMesh smaller = test::make_grid(50, static_cast<int>((slots - 500) / 100));
      ASSERT_LT(smaller.face_slots(), slots);
      const SurfaceMesh tiny = test::make_grid(4, 4);
      for (Kind kind : {bigger, fewer_points, fewer_cells, prepared, coloured, too_small}) {
        SCOPED_TRACE("spare kind " + std::to_string(kind));
        ViewPolyData source_view(*source.mesh, source.positions, &source.normals);
        renumber_points(source_view, source, "the source renumbered");
        const std::vector<vtkTypeInt64> source_cells = connectivity_of(source_view);
        const SurfaceMesh& spare_mesh =
            kind == fewer_points ? sparse : kind == fewer_cells ? smaller : kind == too_small ? tiny : whole;
        ViewPolyData spare(spare_mesh, rest(spare_mesh));
        if (kind == prepared) {
          renumber_points(spare, Drawn{&whole, rest(whole), {}}, "the spare renumbered");
          spare.prepare_updates();
        }
        if (kind == coloured) colour(spare);
        if (kind == fewer_points) {  // (the points' arrays grow)
          ASSERT_LT(4 * spare.poly()->GetNumberOfPoints(), source_view.poly()->GetNumberOfPoints());
        }
        ASSERT_EQ(ViewPolyData::can_take(spare, slots), kind != too_small);
        ViewPolyData copied(*piece.mesh, piece.positions, &piece.normals, source_view, *origin, &spare);
        EXPECT_TRUE(copied.copied());
        EXPECT_EQ(spare.poly() == nullptr, kind != too_small) << "the spare's arrays taken";
        EXPECT_TRUE(connectivity_of(source_view) == source_cells) << "the source changed";
        EXPECT_EQ(copied.poly()->GetPointData()->GetArray("colors"), nullptr);
        EXPECT_EQ(copied.poly()->GetCellData()->GetArray("colors"), nullptr);
        expect_rebuilt(copied, *piece.mesh, piece.positions, &piece.normals, "copied");
        expect_raw_like_fresh(copied, *piece.mesh);
        std::vector<vtkTypeInt64> got = connectivity_of(copied);
        copied.prepare_updates();
        Drawn d = piece;
        renumber_points(copied, d, "prepared, then updated");
        expect_raw_like_fresh(copied, *piece.mesh);
        for (auto& stage : {got, connectivity_of(copied)}) {
          if (threads == 1) first.push_back(stage);
          ASSERT_LT(i, first.size());
          EXPECT_TRUE(stage == first[i++]) << "connectivity differs from one thread's";
        }
      }
    }
    EXPECT_GE(i, 12u) << "no piece large enough";
  }
  set_thread_count(saved);
}

/// Calls `f` with every array `view` draws with (points, point data by name, cells; null when
/// one is missing).
template <class F>
void for_each_array(const ViewPolyData& view, F f) {
  vtkPolyData* poly = view.poly();
  f(poly->GetPoints()->GetData());
  for (const char* name : {"vertex_id", "uv0", "normal"}) f(poly->GetPointData()->GetArray(name));
  f(poly->GetCellData()->GetArray("face_id"));
  f(poly->GetPolys()->GetOffsetsArray64());
  f(poly->GetPolys()->GetConnectivityArray64());
}

/// The raw values of every array `view` draws with.
std::vector<std::vector<char>> raw_arrays(const ViewPolyData& view) {
  std::vector<std::vector<char>> out;
  for_each_array(view, [&](vtkDataArray* a) {
    ASSERT_NE(a, nullptr);
    const auto* from = static_cast<const char*>(a->GetVoidPointer(0));
    out.emplace_back(from, from + a->GetNumberOfValues() * a->GetDataTypeSize());
  });
  return out;
}

// One scratch kept across copying builds, as the studio's view keeps one: the pieces of a cut,
// of another cut of the same model (the first undone), of a smaller model (fewer points, fewer
// chunks of faces) and of a bigger one, each equal to a fresh build and, raw array by raw array,
// to a copy with memory of its own: a build reads nothing an earlier one left in the scratch.
TEST(ViewPolyDataOriginTest, a_kept_scratch_gives_what_own_memory_gives) {
  struct Step {
    int nx, ny;
    Plane plane;
  };
  const Step steps[] = {{160, 120, plane_through({0.1f, 0.0f, 0.1f}, {0.3f, 0.0f, 1.0f})},
                        {160, 120, plane_through({0.6f, 0.0f, 0.3f}, {1.0f, 0.0f, 0.2f})},
                        {30, 20, plane_through({0.37f, 0.0f, 0.41f}, {0.3f, 0.0f, 1.0f})},
                        {200, 150, plane_through({0.5f, 0.0f, 0.5f}, {-0.4f, 0.0f, 1.0f})}};
  ViewPolyData::CopyScratch scratch;
  std::size_t copies = 0;
  for (const Step& step : steps) {
    SCOPED_TRACE("grid " + std::to_string(step.nx) + " x " + std::to_string(step.ny));
    Cut c;
    cut(c, grid_model(step.nx, step.ny), step.plane, -1, 0.0f);
    const PosedModel posed_before = PosedModel::build(c.before, -1, 0.0f, PoseDetail::Positions);
    const PosedModel posed_after = PosedModel::build(c.after, -1, 0.0f, PoseDetail::Positions);
    for (const auto& origin : c.origins) {
      const Drawn source =
          drawn(c.before, posed_before, origin->node_before, origin->mesh_before, origin->primitive_before);
      const Drawn piece = drawn(c.after, posed_after, origin->node, origin->mesh, origin->primitive);
      ASSERT_TRUE(source.mesh && piece.mesh);
      ViewPolyData source_view(*source.mesh, source.positions, &source.normals);
      renumber_points(source_view, source, "the source renumbered");
      const ViewPolyData own(*piece.mesh, piece.positions, &piece.normals, source_view, *origin);
      const ViewPolyData kept(*piece.mesh, piece.positions, &piece.normals, source_view, *origin, nullptr,
                              &scratch);
      ASSERT_TRUE(kept.copied());
      expect_rebuilt(kept, *piece.mesh, piece.positions, &piece.normals, "with the kept scratch");
      EXPECT_TRUE(raw_arrays(kept) == raw_arrays(own)) << "arrays differ from a copy with memory of its own";
      ++copies;
    }
  }
  EXPECT_GE(copies, 8u);
}

/// Every array of `view` holds room for its own elements and a step's growth, and no more than
/// twice that growth past them (ViewPolyData::bytes): each VTK array at most n + n / 4 + 128
/// tuples for its n, and all of them with the lists within a quarter of their bytes and a few
/// kilobytes.
/// With `mesh` (what `view` draws) and its corner lists built, each list holds the same bound for
/// its size (a slot per vertex, or per corner).
void expect_room_bounded(const ViewPolyData& view, const std::string& what,
                         const SurfaceMesh* mesh = nullptr) {
  SCOPED_TRACE(what);
  for_each_array(view, [](vtkDataArray* a) {
    ASSERT_NE(a, nullptr);
    const vtkIdType n = a->GetNumberOfTuples(), components = a->GetNumberOfComponents();
    EXPECT_GE(a->GetSize(), n * components);
    EXPECT_LE(a->GetSize(), (n + n / 4 + 128) * components) << (a->GetName() ? a->GetName() : "points");
  });
  const ViewPolyData::Bytes bytes = view.bytes();
  EXPECT_GT(bytes.used, 0u);
  EXPECT_LE(bytes.held, bytes.used + bytes.used / 4 + 16 * 1024);
  if (!mesh || !view.updates_prepared()) return;
  const std::size_t vertices = mesh->vertex_count(), corners = 3 * mesh->face_slots();
  EXPECT_LE(bytes.lists,
            sizeof(std::uint32_t) * (vertices + vertices / 4 + 3 * (corners + corners / 4) + 4 * 128))
      << "the corner lists";
}

/// `mesh` with `count` more faces, copies of its first live ones (new corners with attributes of
/// their own: new points), and the change to it.
SurfaceMesh with_more_faces(const SurfaceMesh& mesh, std::size_t count, PrimitiveChange& change) {
  SurfaceMesh more = mesh;
  MeshEditor editor(more);
  for (std::uint32_t f = 0; count > 0 && f < mesh.face_slots(); ++f)
    if (!mesh.is_deleted(FaceId(f))) editor.add_face(mesh.faces()[f]), --count;
  EXPECT_TRUE(diff_meshes(mesh, more, change));
  return more;
}

// A small piece of a big cut that takes the whole's data as its spare (prepared: its lists
// too) holds room for its own size, not the spare's; so it does after steps that add faces past
// its room (VTK's own growth would double the arrays), after the step back to its own faces
// (fewer slots: the lists shrink too) and after one that deletes most of them.
TEST(ViewPolyDataOriginTest, a_piece_holds_room_for_its_own_size) {
  Cut c;
  cut(c, grid_model(300, 200), plane_through({0.9f, 0.0f, 0.5f}, {1.0f, 0.0f, 0.1f}), -1, 0.0f);
  const PosedModel posed_before = PosedModel::build(c.before, -1, 0.0f, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(c.after, -1, 0.0f, PoseDetail::Positions);
  const SurfaceMesh& whole = c.before.meshes[0].primitives[0].mesh;
  std::size_t checked = 0;
  for (const auto& origin : c.origins) {
    const Drawn source =
        drawn(c.before, posed_before, origin->node_before, origin->mesh_before, origin->primitive_before);
    const Drawn piece = drawn(c.after, posed_after, origin->node, origin->mesh, origin->primitive);
    ASSERT_TRUE(source.mesh && piece.mesh);
    if (4 * piece.mesh->face_count() > whole.face_count()) continue;  // (the big side)
    const ViewPolyData source_view(*source.mesh, source.positions, &source.normals);
    ViewPolyData spare(*source.mesh, source.positions, &source.normals);
    spare.prepare_updates();
    ASSERT_TRUE(ViewPolyData::can_take(spare, piece.mesh->face_slots()));
    ViewPolyData copied(*piece.mesh, piece.positions, &piece.normals, source_view, *origin, &spare);
    ASSERT_EQ(spare.poly(), nullptr) << "the spare's arrays not taken";
    expect_rebuilt(copied, *piece.mesh, piece.positions, &piece.normals, "copied");
    expect_room_bounded(copied, "copied");
    EXPECT_EQ(copied.bytes().lists, 0u) << "the copy, drawn without corner lists, holds the spare's";
    copied.prepare_updates();
    expect_room_bounded(copied, "prepared", piece.mesh);
    SurfaceMesh mesh = *piece.mesh;
    std::vector<glm::vec3> normals = piece.normals;
    for (int step = 0; step < 3; ++step) {  // a fifth more faces each: past the room of an eighth
      PrimitiveChange change;
      SurfaceMesh more = with_more_faces(mesh, mesh.face_slots() / 5, change);
      normals.resize(3 * more.face_slots(), glm::vec3(0.0f, 1.0f, 0.0f));
      copied.update(more, piece.positions, &normals, change);
      mesh = std::move(more);
      expect_rebuilt(copied, mesh, piece.positions, &normals, "grown, step " + std::to_string(step));
      expect_room_bounded(copied, "grown, step " + std::to_string(step), &mesh);
    }
    {  // a one-face step past the growth moves no array and no list: it costs its own elements
      const std::vector<const void*> blocks = copied.blocks();
      PrimitiveChange change;
      SurfaceMesh more = with_more_faces(mesh, 1, change);
      normals.resize(3 * more.face_slots(), glm::vec3(0.0f, 1.0f, 0.0f));
      copied.update(more, piece.positions, &normals, change);
      mesh = std::move(more);
      expect_rebuilt(copied, mesh, piece.positions, &normals, "one face more");
      EXPECT_EQ(copied.blocks(), blocks) << "a one-face step reallocated an array or a list";
    }
    PrimitiveChange back;  // the growth undone: fewer face slots
    ASSERT_TRUE(diff_meshes(mesh, *piece.mesh, back));
    copied.update(*piece.mesh, piece.positions, &piece.normals, back);
    mesh = *piece.mesh;
    normals = piece.normals;
    expect_rebuilt(copied, mesh, piece.positions, &normals, "growth undone");
    expect_room_bounded(copied, "growth undone", &mesh);
    const SurfaceMesh fewer = sparse_faces(mesh, 10);
    PrimitiveChange change;
    ASSERT_TRUE(diff_meshes(mesh, fewer, change));
    copied.update(fewer, piece.positions, &normals, change);
    expect_rebuilt(copied, fewer, piece.positions, &normals, "most faces deleted");
    expect_room_bounded(copied, "most faces deleted", &fewer);
    ++checked;
  }
  EXPECT_GE(checked, 1u) << "no small piece";
}

}  // namespace
}  // namespace deepcut
