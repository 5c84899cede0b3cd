// SPDX-License-Identifier: MIT
#include "deepcut/core/adjacency.h"

#include <algorithm>
#include <numeric>
#include <type_traits>
#include <variant>

#include "deepcut/core/parallel.h"
#include "union_find.h"

namespace deepcut {
namespace {

// The lists are a vertex's faces, sorted by id (the order is the contract: edge_faces intersects
// two lists, and a rebuild gives the same): a handful of ids, so the elements after an insertion
// or a removal are moved one by one (no call out to memmove). A list of `n` ids at `p`, with room
// for one more; returns the list's new size.
template <class T>
std::uint32_t insert_sorted(T* p, std::uint32_t n, T value) {
  if (n == 0 || p[n - 1] < value) {  // the common case: a new face, the newest id
    p[n] = value;
    return n + 1;
  }
  const auto at = static_cast<std::uint32_t>(std::lower_bound(p, p + n, value) - p);
  if (p[at] == value) return n;
  for (std::uint32_t i = n; i > at; --i) p[i] = p[i - 1];
  p[at] = value;
  return n + 1;
}

// `value` taken out of the sorted list [p, end), the elements after it moved down by one (the
// last element is then stale: the caller drops it); false when it is not there. Found by a scan
// from the front, over a handful of ids cheaper than a binary search, which needs no bound: the
// last element, checked first, is not below `value`. The elements after it are moved one by one
// from the back, each through a register (a plain forward copy loop the compiler turns into a
// call to memmove, which costs more for a handful).
template <class T>
bool erase_sorted(T* p, T* end, T value) {
  if (p == end || end[-1] < value) return false;
  while (*p < value) ++p;
  if (*p != value) return false;
  T carry = end[-1];
  for (T* q = end - 1; q != p;) {
    --q;
    const T moved = *q;
    *q = carry;
    carry = moved;
  }
  return true;
}

// The same on a vertex's own list (the vertices the build saw).
template <class T>
void insert_sorted(std::vector<T>& list, T value) {
  const auto n = static_cast<std::uint32_t>(list.size());
  list.push_back(value);  // the room for one more (taken off again where `value` was there)
  list.resize(insert_sorted(list.data(), n, value));
}

// The index of alternative T in Edit.
template <class T, std::size_t I = 0>
constexpr std::size_t variant_index() {
  if constexpr (std::is_same_v<std::variant_alternative_t<I, Edit>, T>)
    return I;
  else
    return variant_index<T, I + 1>();
}

}  // namespace

// Room every vertex's face list keeps beyond its faces, so the few faces an edit adds around an
// old vertex (a split face leaves two or three where there was one) fit without reallocating
// the list; a vertex an edit makes starts with room for a typical fan, and an added list that
// outgrows its room moves to twice that room.
constexpr std::size_t kListSlack = 4;
constexpr std::uint32_t kNewListRoom = 8;

void Adjacency::add_vertices(std::size_t count) {
  auto at = static_cast<std::uint32_t>(added_pool_.size());
  added_pool_.resize(added_pool_.size() + kNewListRoom * count);
  const std::size_t first = added_.size();
  added_.resize(first + count);
  for (std::size_t i = first; i < added_.size(); ++i, at += kNewListRoom)
    added_[i] = AddedList{at, 0, kNewListRoom};
}

void Adjacency::grow(AddedList& list) {
  const std::uint32_t room = 2 * list.room;
  const auto at = static_cast<std::uint32_t>(added_pool_.size());
  added_pool_.resize(added_pool_.size() + room);
  const auto from = added_pool_.begin() + list.at;
  std::copy(from, from + list.size, added_pool_.begin() + at);
  list.at = at;
  list.room = room;
}

// `apply` has sized the arrays for the log's vertices and faces.
void Adjacency::add_face(FaceId f, const Triangle& t) {
  face_vertices_[f.index] = t;
  const std::size_t old_vertices = vertex_faces_.size();
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t v = t[k].index;
    if (v < old_vertices) {
      // The common case inline: a new face is the newest id in the list, appended (no search).
      std::vector<FaceId>& list = vertex_faces_[v];
      if (list.empty() || list.back() < f)
        list.push_back(f);
      else
        insert_sorted(list, f);
      continue;
    }
    AddedList& list = added_[v - old_vertices];
    if (list.size == list.room) grow(list);
    FaceId* p = added_pool_.data() + list.at;
    if (list.size == 0 || p[list.size - 1] < f)
      p[list.size++] = f;
    else
      list.size = insert_sorted(p, list.size, f);
  }
}

void Adjacency::remove_face(FaceId f, const Triangle& t) {
  if (f.index < face_vertices_.size()) face_vertices_[f.index] = Triangle{};
  const std::size_t old_vertices = vertex_faces_.size(), vertices = vertex_count();
  for (const VertexId v : t) {
    if (v.index < old_vertices) {
      std::vector<FaceId>& list = vertex_faces_[v.index];
      if (erase_sorted(list.data(), list.data() + list.size(), f)) list.pop_back();
    } else if (v.index < vertices) {
      AddedList& list = added_[v.index - old_vertices];
      FaceId* p = added_pool_.data() + list.at;
      if (erase_sorted(p, p + list.size, f)) --list.size;
    }
  }
}

Adjacency::Adjacency(const Adjacency& other)
    : added_(other.added_), added_pool_(other.added_pool_), face_vertices_(other.face_vertices_) {
  vertex_faces_.resize(other.vertex_faces_.size());
  for (std::size_t v = 0; v < vertex_faces_.size(); ++v) {
    const auto& from = other.vertex_faces_[v];
    vertex_faces_[v].reserve(from.size() + kListSlack);
    vertex_faces_[v].assign(from.begin(), from.end());
  }
}

Adjacency& Adjacency::operator=(const Adjacency& other) {
  if (this != &other) *this = Adjacency(other);
  return *this;
}

void Adjacency::reserve(std::size_t vertices, std::size_t faces) {
  // New vertices' lists, and added lists that outgrow their room, fit in added_pool_'s room.
  const std::size_t more_vertices = vertices > vertex_count() ? vertices - vertex_count() : 0;
  added_.reserve(added_.size() + more_vertices);
  added_pool_.reserve(added_pool_.size() + 2 * kNewListRoom * more_vertices);
  face_vertices_.reserve(faces);
  // A copied adjacency's lists hold exactly their faces: give them back their room.
  parallel_for(vertex_faces_.size(), 8192, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      auto& list = vertex_faces_[v];
      if (list.capacity() < list.size() + kListSlack) list.reserve(list.size() + kListSlack);
    }
  });
}

Adjacency Adjacency::build(const SurfaceMesh& mesh) {
  Adjacency adj;
  const std::size_t nv = mesh.vertex_count();
  const auto& faces = mesh.faces();
  // Counting sort of the corners by vertex (faces in increasing id, so every list comes out
  // sorted), then each vertex's list is copied out, in parallel chunks of vertices.
  std::vector<std::uint32_t> start(nv + 1, 0);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) ++start[t[k].index + 1];
  });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<FaceId> incident(start[nv]);
  {
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      for (int k = 0; k < 3; ++k) incident[next[t[k].index]++] = f;
    });
  }
  adj.vertex_faces_.resize(nv);
  parallel_for(nv, 8192, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      // A face using the vertex twice (a degenerate fold) is listed once.
      const FaceId* first = incident.data() + start[v];
      const FaceId* last = incident.data() + start[v + 1];
      auto& list = adj.vertex_faces_[v];
      list.reserve(static_cast<std::size_t>(last - first) + kListSlack);
      for (const FaceId* f = first; f != last; ++f)
        if (list.empty() || list.back() != *f) list.push_back(*f);
    }
  });
  adj.face_vertices_.resize(faces.size());
  parallel_for(faces.size(), 32768, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f)
      adj.face_vertices_[f] = mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))) ? Triangle{} : faces[f];
  });
  return adj;
}

void Adjacency::apply(const EditLog& log) {
  // Sized once for the vertices and face slots the log names, so the edits below never grow
  // the outer arrays one element at a time.
  // One switch on the alternative's index per edit (no chain of get_if, no visit table).
  constexpr std::size_t kVertexAdded = variant_index<VertexAdded>(),
                        kVertexSplit = variant_index<VertexSplit>(), kFaceAdded = variant_index<FaceAdded>(),
                        kFaceRemoved = variant_index<FaceRemoved>();
  std::uint32_t vertices = 0, faces = 0;
  for (const Edit& edit : log.edits) {
    switch (edit.index()) {
      case kFaceAdded: {
        const auto& a = *std::get_if<kFaceAdded>(&edit);
        faces = std::max(faces, a.f.index + 1);
        vertices =
            std::max({vertices, a.vertices[0].index + 1, a.vertices[1].index + 1, a.vertices[2].index + 1});
        break;
      }
      case kVertexAdded:
        vertices = std::max(vertices, std::get_if<kVertexAdded>(&edit)->v.index + 1);
        break;
      case kVertexSplit:
        vertices = std::max(vertices, std::get_if<kVertexSplit>(&edit)->copy.index + 1);
        break;
      default:
        break;
    }
  }
  if (vertices > vertex_count()) add_vertices(vertices - vertex_count());
  if (faces > face_vertices_.size()) face_vertices_.resize(faces, Triangle{});
  for (const Edit& edit : log.edits) {
    const std::size_t kind = edit.index();
    if (kind == kFaceAdded) {
      const auto& e = *std::get_if<kFaceAdded>(&edit);
      add_face(e.f, e.vertices);
    } else if (kind == kFaceRemoved) {
      const auto& e = *std::get_if<kFaceRemoved>(&edit);
      remove_face(e.f, e.vertices);
    }
  }
}

std::vector<VertexId> Adjacency::vertex_neighbors(VertexId v) const {
  std::vector<VertexId> out;
  for (FaceId f : vertex_faces(v))
    for (VertexId u : face_vertices_[f.index])
      if (u != v) out.push_back(u);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<FaceId> Adjacency::edge_faces(VertexId u, VertexId v) const {
  std::vector<FaceId> out;
  if (u == v || u.index >= vertex_count() || v.index >= vertex_count()) return out;
  const VertexFaces a = vertex_faces(u), b = vertex_faces(v);
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

std::vector<FaceId> Adjacency::face_neighbors(FaceId f) const {
  std::vector<FaceId> out;
  if (f.index >= face_vertices_.size() || !face_vertices_[f.index][0].valid()) return out;
  const auto& t = face_vertices_[f.index];
  for (int k = 0; k < 3; ++k)
    for (FaceId g : edge_faces(t[k], t[(k + 1) % 3]))
      if (g != f) out.push_back(g);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

template <class Fn>
void Adjacency::for_each_edge(Fn&& fn) const {
  // Each edge is reported from its lowest-numbered face, so exactly once.
  for (std::uint32_t f = 0; f < face_vertices_.size(); ++f) {
    const auto& t = face_vertices_[f];
    if (!t[0].valid()) continue;
    for (int k = 0; k < 3; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      if (a == b) continue;
      const auto faces = edge_faces(a, b);
      if (faces.empty() || faces.front() != FaceId(f)) continue;
      // A face listing the same edge twice (a degenerate fold) reports it from its first corner only.
      bool earlier = false;
      for (int j = 0; j < k; ++j) earlier |= make_edge(t[j], t[(j + 1) % 3]) == make_edge(a, b);
      if (!earlier) fn(make_edge(a, b), faces);
    }
  }
}

std::size_t Adjacency::edge_count() const {
  std::size_t n = 0;
  for_each_edge([&](const Edge&, const std::vector<FaceId>&) { ++n; });
  return n;
}

std::vector<Edge> Adjacency::boundary_edges() const {
  std::vector<Edge> out;
  for_each_edge([&](const Edge& e, const std::vector<FaceId>& faces) {
    if (faces.size() == 1) out.push_back(e);
  });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Edge> Adjacency::nonmanifold_edges() const {
  std::vector<Edge> out;
  for_each_edge([&](const Edge& e, const std::vector<FaceId>& faces) {
    if (faces.size() > 2) out.push_back(e);
  });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Edge> Adjacency::seam_edges(const SurfaceMesh& mesh) const {
  std::vector<Edge> out;
  const auto& ca = mesh.corner_attrs();
  auto corner_of = [&](FaceId f, VertexId v) {
    const auto& t = mesh.face(f);
    for (int k = 0; k < 3; ++k)
      if (t[k] == v) return SurfaceMesh::corner(f, k);
    return kInvalidIndex;
  };
  for_each_edge([&](const Edge& e, const std::vector<FaceId>& faces) {
    if (faces.size() != 2) return;
    const bool same = ca.elements_equal(corner_of(faces[0], e.a), corner_of(faces[1], e.a)) &&
                      ca.elements_equal(corner_of(faces[0], e.b), corner_of(faces[1], e.b));
    if (!same) out.push_back(e);
  });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::uint32_t> Adjacency::vertex_components(std::size_t* count) const {
  const auto n = static_cast<std::uint32_t>(vertex_count());
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (const auto& t : face_vertices_) {
    if (!t[0].valid()) continue;
    for (int k = 1; k < 3; ++k) {
      const auto r0 = detail::find_root(parent, t[0].index), rk = detail::find_root(parent, t[k].index);
      if (r0 != rk) parent[std::max(r0, rk)] = std::min(r0, rk);
    }
  }
  std::vector<std::uint32_t> label(n, kInvalidIndex), root_label(n, kInvalidIndex);
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (vertex_faces(VertexId(v)).empty()) continue;
    const auto r = detail::find_root(parent, v);
    if (root_label[r] == kInvalidIndex) root_label[r] = next++;
    label[v] = root_label[r];
  }
  if (count) *count = next;
  return label;
}

std::size_t Adjacency::component_count() const {
  std::size_t count = 0;
  vertex_components(&count);
  return count;
}

bool Adjacency::operator==(const Adjacency& other) const {
  if (vertex_count() != other.vertex_count()) return false;
  for (std::uint32_t v = 0; v < vertex_count(); ++v) {
    const VertexFaces a = vertex_faces(VertexId(v)), b = other.vertex_faces(VertexId(v));
    if (!std::equal(a.begin(), a.end(), b.begin(), b.end())) return false;
  }
  // Face slots beyond the shorter list must all be removed ones.
  const std::size_t n = std::max(face_vertices_.size(), other.face_vertices_.size());
  for (std::size_t f = 0; f < n; ++f) {
    const Triangle a = f < face_vertices_.size() ? face_vertices_[f] : Triangle{};
    const Triangle b = f < other.face_vertices_.size() ? other.face_vertices_[f] : Triangle{};
    if (a != b) return false;
  }
  return true;
}

}  // namespace deepcut
