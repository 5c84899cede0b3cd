// SPDX-License-Identifier: MIT
#pragma once
// What both builds of the view data and its updates write with: the arrays of a view poly data
// by raw storage, and the Writer that fills points and cells from one state of the mesh (the one
// kernel of every build and update), with a vertex's list of corners. Shared by the full build
// and updates (view_poly_data.cpp) and the copying build (view_poly_data_copy.cpp).

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTypeInt64Array.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "deepcut/core/morph.h"
#include "deepcut/widgets/view_poly_data.h"

namespace deepcut {
namespace view_data {

// Elements per task of the passes over the pool.
constexpr std::size_t kGrain = 16384;

// The room (a size, not "room for n more") every array of the data gets for `n` elements:
// theirs and a step's growth (a step appends a few elements: no reallocation of the whole array
// each time; a reallocation costs in proportion to the array, and so does the room), sized by the
// data's own elements, not by data whose memory it took over. The model's arrays get an eighth
// and a thousand or two (core's operation_room.h: a few primitives, each edited again and again);
// a long session draws a hundred pieces and more, each with a dozen arrays here: an eighth and a
// few dozen elements, not thousands, for each of them.
inline std::size_t room_size(std::size_t n) { return n + n / 8 + 64; }
// Whether `held` elements are too much room for `n`: more than n + 2 x (n / 8 + 64), twice the
// growth room_size gives past n (memory taken over from bigger data, or left as the data
// shrank): given back down to room_size(n). Up to that, the room stays, so that a step that
// removes a few elements and the next that adds them do not reallocate.
inline bool too_roomy(std::size_t held, std::size_t n) { return held > n + n / 4 + 128; }

// Room for `n` elements of `v` before it grows to them (its values kept): room_size(n) when it
// has less (not the doubling of a vector's own growth).
template <class T>
void grow(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(room_size(n));
}

// `v`'s values in room_size of their own when it holds too much room for them (too_roomy).
template <class T>
void fit(std::vector<T>& v) {
  if (!too_roomy(v.capacity(), v.size())) return;
  std::vector<T> fitted;
  fitted.reserve(room_size(v.size()));
  fitted.assign(v.begin(), v.end());
  v.swap(fitted);
}

// Gives `v` room for `room` >= its next size: the memory it has unless that is too small or too
// roomy for `room` (then, the old values and memory dropped first, room_size(room) of its own).
template <class T>
void make_room(std::vector<T>& v, std::size_t room) {
  if (room > v.capacity() || too_roomy(v.capacity(), room)) {
    std::vector<T>().swap(v);  // (the old memory goes first)
    v.reserve(room_size(room));
  }
}

// `v` made `n` copies of `value`, with room for `room` (make_room).
template <class T>
void refill(std::vector<T>& v, std::size_t n, const T& value, std::size_t room = 0) {
  make_room(v, std::max(n, room));
  v.assign(n, value);
}

// `v` sized `n` for a caller that writes every element: in memory it keeps, only the elements
// past its old size are written here (by resize), no pass over all `n`; room for `room` (make_room).
template <class T>
void resize_to_write(std::vector<T>& v, std::size_t n, std::size_t room = 0) {
  make_room(v, std::max(n, room));
  v.resize(n);
}

template <class Array>
inline Array* named(vtkDataSetAttributes* data, const char* name) {
  return Array::SafeDownCast(data->GetArray(name));
}

// The arrays of a view poly data, by raw storage (valid until the next set_point_count, resize
// or set_count: each may move an array).
struct Raw {
  float* points = nullptr;
  float* normals = nullptr;
  float* uv = nullptr;
  vtkIdType* vertex_id = nullptr;
  vtkIdType* face_id = nullptr;
  vtkTypeInt64* offsets = nullptr;
  vtkTypeInt64* connectivity = nullptr;
};

inline Raw raw(vtkPolyData* poly) {
  Raw r;
  vtkPointData* pd = poly->GetPointData();
  r.points = vtkFloatArray::SafeDownCast(poly->GetPoints()->GetData())->GetPointer(0);
  if (auto* a = vtkFloatArray::SafeDownCast(pd->GetNormals())) r.normals = a->GetPointer(0);
  if (auto* a = named<vtkFloatArray>(pd, "uv0")) r.uv = a->GetPointer(0);  // active or not
  r.vertex_id = named<vtkIdTypeArray>(pd, "vertex_id")->GetPointer(0);
  r.face_id = named<vtkIdTypeArray>(poly->GetCellData(), "face_id")->GetPointer(0);
  r.offsets = poly->GetPolys()->GetOffsetsArray64()->GetPointer(0);
  r.connectivity = poly->GetPolys()->GetConnectivityArray64()->GetPointer(0);
  return r;
}

// Point `p`'s position and, when both are there, normal: what a build, an update and a new
// pose all write. Three stores each, which stay inline in the per-point loops (a copy of three
// floats need not).
inline void write_point(const Raw& r, std::size_t p, const glm::vec3& position, const glm::vec3* normal) {
  float* const to = r.points + 3 * p;
  to[0] = position.x, to[1] = position.y, to[2] = position.z;
  if (r.normals && normal) {
    float* const n = r.normals + 3 * p;
    n[0] = normal->x, n[1] = normal->y, n[2] = normal->z;
  }
}

// A point no corner draws (what a deleted face's cell names when no other point is left).
inline void clear_point(const Raw& r, std::size_t p) {
  std::fill(r.points + 3 * p, r.points + 3 * p + 3, 0.0f);
  r.vertex_id[p] = 0;
  if (r.uv) std::fill(r.uv + 2 * p, r.uv + 2 * p + 2, 0.0f);
  if (r.normals) std::fill(r.normals + 3 * p, r.normals + 3 * p + 3, 0.0f);
}

}  // namespace view_data

// Writes elements of one state of the mesh into the arrays: the one kernel of the whole build
// and of every update.
struct ViewPolyData::Writer {
  view_data::Raw r;
  const SurfaceMesh& mesh;
  const std::vector<glm::vec3>& positions;
  const glm::vec3* normals = nullptr;  // posed corner normals, else the mesh's (or none)
  const glm::vec2* uv = nullptr;
  // What else decides a corner's normal in some pose: the mesh's normals (when posed ones are
  // drawn) and the morph normal deltas.
  std::vector<const glm::vec3*> normal_sources;

  Writer(vtkPolyData* poly, const SurfaceMesh& m, const std::vector<glm::vec3>& p,
         const std::vector<glm::vec3>* n)
      : r(view_data::raw(poly)), mesh(m), positions(p) {
    const auto& ca = m.corner_attrs();
    if (const auto* a = ca.find<glm::vec2>(attr::kUv0)) uv = a->data().data();
    const auto* own = ca.find<glm::vec3>(attr::kNormal);
    if (n && !n->empty()) {
      normals = n->data();
      if (own) normal_sources.push_back(own->data().data());
    } else if (own) {
      normals = own->data().data();
    }
    for (int t = 0, targets = morph_target_count(m); t < targets; ++t)
      if (const auto* a = ca.find<glm::vec3>(attr::morph_normal_name(t)))
        normal_sources.push_back(a->data().data());
  }

  void refresh(vtkPolyData* poly) { r = view_data::raw(poly); }

  // Corners `a` and `b` (of one vertex) draw alike in every pose: bit for bit.
  bool alike(std::size_t a, std::size_t b) const {
    auto same3 = [&](const glm::vec3* x) { return std::memcmp(&x[a], &x[b], sizeof(glm::vec3)) == 0; };
    if (normals && !same3(normals)) return false;
    if (uv && std::memcmp(&uv[a], &uv[b], sizeof(glm::vec2)) != 0) return false;
    return std::all_of(normal_sources.begin(), normal_sources.end(), same3);
  }

  // Point `p` draws vertex `v` as corner `c` does.
  void point(std::size_t p, std::uint32_t v, std::size_t c) const {
    view_data::write_point(r, p, positions[v], normals ? &normals[c] : nullptr);
    r.vertex_id[p] = v;
    if (r.uv && uv) {
      r.uv[2 * p] = uv[c].x;
      r.uv[2 * p + 1] = uv[c].y;
    }
  }

  void vertex_cell(std::size_t f) const {
    const FaceId face(static_cast<std::uint32_t>(f));
    const Triangle& t = mesh.face(face);
    const bool deleted = mesh.is_deleted(face);
    for (int k = 0; k < 3; ++k)
      r.connectivity[3 * f + static_cast<std::size_t>(k)] = deleted ? 0 : t[k].index;
  }

  void vertex_point(std::size_t v) const {
    view_data::write_point(r, v, positions[v], nullptr);
    r.vertex_id[v] = static_cast<vtkIdType>(v);
  }
};

// The corners of one vertex: its linked list (from `head` through `next`), or a list of its own.
struct ViewPolyData::Corners {
  const std::uint32_t* next = nullptr;
  std::uint32_t head = kInvalidIndex;
  const std::uint32_t *begin = nullptr, *end = nullptr;
  // Calls `fn(c)` for each corner in order until it returns true. @returns whether one did.
  template <class Fn>
  bool any(const Fn& fn) const {
    if (next) {
      for (std::uint32_t c = head; c != kInvalidIndex; c = next[c])
        if (fn(c)) return true;
      return false;
    }
    return std::any_of(begin, end, fn);
  }
};

}  // namespace deepcut
