// SPDX-License-Identifier: MIT
#include "deepcut/widgets/poly_data_bridge.h"

#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnsignedShortArray.h>

namespace deepcut {

namespace {

/// The points of a conversion: one per (vertex, uv, normal) when corners are split, per vertex
/// otherwise, in the order the faces' corners first name them.
struct PointMap {
  std::vector<std::uint32_t> point_vertex, point_corner;  ///< per point: its vertex, its first corner
  std::vector<vtkIdType> corner_point;                    ///< per corner slot: its point (-1: none)
};

/// Adds a point for corner `c` of vertex `v` to `map`; its id.
vtkIdType add_point(std::uint32_t v, std::uint32_t c, PointMap& map) {
  map.point_vertex.push_back(v);
  map.point_corner.push_back(c);
  return static_cast<vtkIdType>(map.point_vertex.size() - 1);
}

/// Finds a corner's point among those of the same vertex, uv and normal met so far, by a hash of
/// (vertex, uv, normal).
class CornerPoints {
 public:
  CornerPoints(const AttributeArray<glm::vec2>* uv, const AttributeArray<glm::vec3>* normal)
      : uv_(uv), normal_(normal) {}

  /// The point of corner `c` of vertex `v`: one met so far with the same uv and normal, or a new
  /// one added to `map`.
  vtkIdType find_or_add(std::uint32_t v, std::uint32_t c, PointMap& map) {
    std::uint64_t h = v;
    if (uv_) h = h * 1000003u ^ std::hash<float>()((*uv_)[c].x) ^ (std::hash<float>()((*uv_)[c].y) << 1);
    if (normal_)
      h = h * 1000003u ^ std::hash<float>()((*normal_)[c].x) ^ (std::hash<float>()((*normal_)[c].z) << 1);
    auto range = seen_.equal_range(h);
    for (auto it = range.first; it != range.second; ++it)
      if (map.point_vertex[std::size_t(it->second)] == v &&
          same_corner(map.point_corner[std::size_t(it->second)], c))
        return it->second;
    const vtkIdType id = add_point(v, c, map);
    seen_.emplace(h, id);
    return id;
  }

 private:
  bool same_corner(std::uint32_t a, std::uint32_t b) const {
    return (!uv_ || (*uv_)[a] == (*uv_)[b]) && (!normal_ || (*normal_)[a] == (*normal_)[b]);
  }
  const AttributeArray<glm::vec2>* uv_;
  const AttributeArray<glm::vec3>* normal_;
  std::unordered_multimap<std::uint64_t, vtkIdType> seen_;
};

PointMap map_points(const SurfaceMesh& mesh, const AttributeArray<glm::vec2>* uv,
                    const AttributeArray<glm::vec3>* normal) {
  PointMap map;
  map.corner_point.assign(3 * mesh.face_slots(), -1);
  std::vector<vtkIdType> vertex_point(mesh.vertex_count(), -1);
  CornerPoints split(uv, normal);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t c = SurfaceMesh::corner(f, k), v = t[k].index;
      if (uv || normal) {
        map.corner_point[c] = split.find_or_add(v, c, map);
        continue;
      }
      if (vertex_point[v] < 0) vertex_point[v] = add_point(v, c, map);
      map.corner_point[c] = vertex_point[v];
    }
  });
  return map;
}

/// The points at `pos` with their vertex and corner ids ("vertex_id", "corner_id"), and a
/// triangle per live face with its face id ("face_id").
vtkSmartPointer<vtkPolyData> points_and_cells(const SurfaceMesh& mesh, const std::vector<glm::vec3>& pos,
                                              const PointMap& map) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(static_cast<vtkIdType>(map.point_vertex.size()));
  vtkNew<vtkIdTypeArray> vertex_ids;
  vertex_ids->SetName("vertex_id");
  vertex_ids->SetNumberOfValues(points->GetNumberOfPoints());
  vtkNew<vtkIdTypeArray> corner_ids;
  corner_ids->SetName("corner_id");
  corner_ids->SetNumberOfValues(points->GetNumberOfPoints());
  for (std::size_t i = 0; i < map.point_vertex.size(); ++i) {
    const auto& p = pos[map.point_vertex[i]];
    points->SetPoint(static_cast<vtkIdType>(i), p.x, p.y, p.z);
    vertex_ids->SetValue(static_cast<vtkIdType>(i), map.point_vertex[i]);
    corner_ids->SetValue(static_cast<vtkIdType>(i), map.point_corner[i]);
  }
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkIdTypeArray> face_ids;
  face_ids->SetName("face_id");
  mesh.for_each_face([&](FaceId f, const Triangle&) {
    const vtkIdType ids[3] = {map.corner_point[SurfaceMesh::corner(f, 0)],
                              map.corner_point[SurfaceMesh::corner(f, 1)],
                              map.corner_point[SurfaceMesh::corner(f, 2)]};
    polys->InsertNextCell(3, ids);
    face_ids->InsertNextValue(f.index);
  });
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  poly->GetPointData()->AddArray(vertex_ids);
  poly->GetPointData()->AddArray(corner_ids);
  poly->GetCellData()->AddArray(face_ids);
  return poly;
}

/// A point array `name` of `components` per point: point i's is values[from[i]].
template <class Array, class Values>
vtkSmartPointer<Array> gathered(const char* name, int components, const Values& values,
                                const std::vector<std::uint32_t>& from) {
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  const auto n = static_cast<vtkIdType>(from.size());
  a->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i) a->SetTypedTuple(i, &values[from[std::size_t(i)]].x);
  return a;
}

}  // namespace

vtkSmartPointer<vtkPolyData> to_poly_data(const SurfaceMesh& mesh, const PolyDataOptions& options) {
  const auto& pos = options.positions ? *options.positions : mesh.positions();
  const auto& ca = mesh.corner_attrs();
  const auto* uv = options.split_corners ? ca.find<glm::vec2>(attr::kUv0) : nullptr;
  const auto* normal = options.split_corners ? ca.find<glm::vec3>(attr::kNormal) : nullptr;
  const PointMap map = map_points(mesh, uv, normal);
  vtkSmartPointer<vtkPolyData> poly = points_and_cells(mesh, pos, map);
  vtkPointData* data = poly->GetPointData();
  if (uv) data->SetTCoords(gathered<vtkFloatArray>("uv0", 2, *uv, map.point_corner));
  if (normal) data->SetNormals(gathered<vtkFloatArray>("normal", 3, *normal, map.point_corner));
  const auto& va = mesh.vertex_attrs();
  if (const auto* j = va.find<glm::u16vec4>(attr::kJoints0))
    data->AddArray(gathered<vtkUnsignedShortArray>("joints0", 4, *j, map.point_vertex));
  if (const auto* w = va.find<glm::vec4>(attr::kWeights0))
    data->AddArray(gathered<vtkFloatArray>("weights0", 4, *w, map.point_vertex));
  return poly;
}

namespace {

vtkIdTypeArray* id_array(vtkDataSetAttributes* data, const char* name, const char* function) {
  auto* array = vtkIdTypeArray::SafeDownCast(data ? data->GetArray(name) : nullptr);
  if (!array)
    throw Error(ErrorCode::InvalidArgument,
                std::string(function) + ": the poly data has no '" + name + "' array (make it with to_poly_data)");
  return array;
}

vtkSmartPointer<vtkUnsignedCharArray> color_array(vtkIdTypeArray* ids, const std::vector<glm::u8vec3>& colors,
                                                  const char* function) {
  auto out = vtkSmartPointer<vtkUnsignedCharArray>::New();
  out->SetName("colors");
  out->SetNumberOfComponents(3);
  out->SetNumberOfTuples(ids->GetNumberOfTuples());
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i) {
    const vtkIdType e = ids->GetValue(i);
    if (e < 0 || static_cast<std::size_t>(e) >= colors.size())
      throw Error(ErrorCode::InvalidArgument, std::string(function) + ": element " + std::to_string(e) + " has no colour (" +
                                                  std::to_string(colors.size()) + " given)");
    out->SetTypedTuple(i, &colors[static_cast<std::size_t>(e)].x);
  }
  return out;
}

}  // namespace

void update_poly_data_points(vtkPolyData* poly, const std::vector<glm::vec3>& positions,
                             const std::vector<glm::vec3>* corner_normals) {
  vtkIdTypeArray* vertex_ids = id_array(poly->GetPointData(), "vertex_id", "update_poly_data_points");
  vtkPoints* points = poly->GetPoints();
  const vtkIdType n = vertex_ids->GetNumberOfTuples();
  if (!points || points->GetNumberOfPoints() != n)
    throw Error(ErrorCode::InvalidArgument, "update_poly_data_points: point count does not match 'vertex_id'");
  for (vtkIdType i = 0; i < n; ++i) {
    const vtkIdType v = vertex_ids->GetValue(i);
    if (v < 0 || static_cast<std::size_t>(v) >= positions.size())
      throw Error(ErrorCode::InvalidArgument, "update_poly_data_points: vertex " + std::to_string(v) + " has no position (" +
                                                  std::to_string(positions.size()) + " given)");
    const glm::vec3& p = positions[static_cast<std::size_t>(v)];
    points->SetPoint(i, p.x, p.y, p.z);
  }
  points->Modified();
  auto* normals = vtkFloatArray::SafeDownCast(poly->GetPointData()->GetNormals());
  if (corner_normals && !corner_normals->empty() && normals) {
    vtkIdTypeArray* corner_ids = id_array(poly->GetPointData(), "corner_id", "update_poly_data_points");
    for (vtkIdType i = 0; i < n; ++i) {
      const vtkIdType c = corner_ids->GetValue(i);
      if (c < 0 || static_cast<std::size_t>(c) >= corner_normals->size())
        throw Error(ErrorCode::InvalidArgument, "update_poly_data_points: corner " + std::to_string(c) + " has no normal");
      normals->SetTypedTuple(i, &(*corner_normals)[static_cast<std::size_t>(c)].x);
    }
    normals->Modified();
  }
  poly->Modified();
}

void set_vertex_colors(vtkPolyData* poly, const std::vector<glm::u8vec3>& vertex_colors) {
  auto colors = color_array(id_array(poly->GetPointData(), "vertex_id", "set_vertex_colors"), vertex_colors,
                            "set_vertex_colors");
  poly->GetCellData()->RemoveArray("colors");
  poly->GetPointData()->RemoveArray("colors");
  poly->GetPointData()->SetScalars(colors);
  poly->Modified();
}

void set_face_colors(vtkPolyData* poly, const std::vector<glm::u8vec3>& face_colors) {
  auto colors = color_array(id_array(poly->GetCellData(), "face_id", "set_face_colors"), face_colors, "set_face_colors");
  poly->GetPointData()->RemoveArray("colors");
  poly->GetCellData()->RemoveArray("colors");
  poly->GetCellData()->SetScalars(colors);
  poly->Modified();
}

void clear_colors(vtkPolyData* poly) {
  poly->GetPointData()->RemoveArray("colors");
  poly->GetCellData()->RemoveArray("colors");
  poly->Modified();
}

SurfaceMesh from_poly_data(vtkPolyData* poly) {
  SurfaceMesh mesh;
  const vtkIdType np = poly->GetNumberOfPoints();
  mesh.reserve(static_cast<std::size_t>(np), static_cast<std::size_t>(poly->GetNumberOfPolys()));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    poly->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw Error(ErrorCode::InvalidInput, "from_poly_data: point " + std::to_string(i) + " is not finite");
    mesh.add_vertex(glm::vec3(p[0], p[1], p[2]));
  }
  vtkCellArray* polys = poly->GetPolys();
  if (!polys) return mesh;
  vtkNew<vtkIdList> cell;
  polys->InitTraversal();
  while (polys->GetNextCell(cell)) {
    for (vtkIdType k = 2; k < cell->GetNumberOfIds(); ++k)
      mesh.add_face(VertexId(static_cast<std::uint32_t>(cell->GetId(0))), VertexId(static_cast<std::uint32_t>(cell->GetId(k - 1))),
                    VertexId(static_cast<std::uint32_t>(cell->GetId(k))));
  }
  return mesh;
}

}  // namespace deepcut
