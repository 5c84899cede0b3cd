// SPDX-License-Identifier: MIT
#include "deepcut/core/surface_mesh.h"

#include <algorithm>
#include <string>
#include <utility>

namespace deepcut {

SurfaceMesh::SurfaceMesh() { positions_ = &vattrs_.add<glm::vec3>(attr::kPosition); }

// A copy keeps the room reserved for growth (as the attribute arrays do), so an operation on a
// copy of a session's model (the studio's undo snapshots) does not reallocate every array.
SurfaceMesh::SurfaceMesh(const SurfaceMesh& other)
    : deleted_count_(other.deleted_count_),
      vattrs_(other.vattrs_),
      fattrs_(other.fattrs_),
      cattrs_(other.cattrs_),
      positions_(vattrs_.find<glm::vec3>(attr::kPosition)) {
  faces_.reserve(other.faces_.capacity());
  faces_.assign(other.faces_.begin(), other.faces_.end());
  deleted_.reserve(other.deleted_.capacity());
  deleted_.assign(other.deleted_.begin(), other.deleted_.end());
}

SurfaceMesh& SurfaceMesh::operator=(const SurfaceMesh& other) {
  if (this != &other) {
    SurfaceMesh copy(other);
    *this = std::move(copy);
  }
  return *this;
}

// Moving an AttributeSet moves its std::map, whose nodes (and the arrays they own) stay put, so
// positions_ can be carried over.
SurfaceMesh::SurfaceMesh(SurfaceMesh&& other) noexcept
    : faces_(std::move(other.faces_)),
      deleted_(std::move(other.deleted_)),
      deleted_count_(other.deleted_count_),
      vattrs_(std::move(other.vattrs_)),
      fattrs_(std::move(other.fattrs_)),
      cattrs_(std::move(other.cattrs_)),
      positions_(other.positions_),
      observer_(other.observer_),
      observer_id_(other.observer_id_) {
  other.observer_ = nullptr;
  other.deleted_count_ = 0;
  other.vattrs_ = AttributeSet();
  other.fattrs_ = AttributeSet();
  other.cattrs_ = AttributeSet();
  other.positions_ = &other.vattrs_.add<glm::vec3>(attr::kPosition);
}

SurfaceMesh& SurfaceMesh::operator=(SurfaceMesh&& other) noexcept {
  if (this != &other) {
    if (observer_) release();
    observer_ = other.observer_;
    observer_id_ = other.observer_id_;
    other.observer_ = nullptr;
    faces_ = std::move(other.faces_);
    deleted_ = std::move(other.deleted_);
    deleted_count_ = other.deleted_count_;
    vattrs_ = std::move(other.vattrs_);
    fattrs_ = std::move(other.fattrs_);
    cattrs_ = std::move(other.cattrs_);
    positions_ = other.positions_;
    other.faces_.clear();
    other.deleted_.clear();
    other.deleted_count_ = 0;
    other.vattrs_ = AttributeSet();
    other.fattrs_ = AttributeSet();
    other.cattrs_ = AttributeSet();
    other.positions_ = &other.vattrs_.add<glm::vec3>(attr::kPosition);
  }
  return *this;
}

SurfaceMesh::~SurfaceMesh() {
  if (observer_) release();
}

void SurfaceMesh::release() {
  MeshObserver* observer = observer_;
  observer_ = nullptr;
  observer->released(observer_id_, std::move(*this));
}

std::size_t MeshTail::bytes() const {
  return faces.capacity() * sizeof(Triangle) + deleted.capacity() + vertex_attrs.capacity_bytes() +
         face_attrs.capacity_bytes() + corner_attrs.capacity_bytes();
}

MeshTail SurfaceMesh::take_tail(std::size_t vertices, std::size_t faces) {
  MeshTail tail;
  std::vector<std::uint32_t> vs, fs, cs;
  for (std::size_t v = vertices; v < vertex_count(); ++v) vs.push_back(static_cast<std::uint32_t>(v));
  for (std::size_t f = faces; f < face_slots(); ++f) {
    fs.push_back(static_cast<std::uint32_t>(f));
    for (std::uint32_t k = 0; k < 3; ++k) cs.push_back(static_cast<std::uint32_t>(3 * f + k));
  }
  tail.faces.assign(faces_.begin() + static_cast<std::ptrdiff_t>(faces), faces_.end());
  tail.deleted.assign(deleted_.begin() + static_cast<std::ptrdiff_t>(faces), deleted_.end());
  tail.vertex_attrs = vattrs_.subset(vs);
  tail.face_attrs = fattrs_.subset(fs);
  tail.corner_attrs = cattrs_.subset(cs);
  for (std::uint8_t d : tail.deleted) deleted_count_ -= d != 0;
  faces_.resize(faces);
  deleted_.resize(faces);
  vattrs_.resize(vertices);
  fattrs_.resize(faces);
  cattrs_.resize(3 * faces);
  return tail;
}

void SurfaceMesh::append_tail(const MeshTail& tail) {
  vattrs_.append_from(tail.vertex_attrs, 0, tail.vertex_attrs.size());
  fattrs_.append_from(tail.face_attrs, 0, tail.face_attrs.size());
  cattrs_.append_from(tail.corner_attrs, 0, tail.corner_attrs.size());
  faces_.insert(faces_.end(), tail.faces.begin(), tail.faces.end());
  deleted_.insert(deleted_.end(), tail.deleted.begin(), tail.deleted.end());
  for (std::uint8_t d : tail.deleted) deleted_count_ += d != 0;
}

void SurfaceMesh::swap_face(FaceId f, Triangle& corners, std::uint8_t& deleted) {
  std::swap(faces_[f.index], corners);
  const bool was = deleted_[f.index] != 0;
  deleted_[f.index] = deleted ? 1 : 0;
  deleted = was ? 1 : 0;
  deleted_count_ = deleted_count_ - (was ? 1 : 0) + (deleted_[f.index] ? 1 : 0);
}

std::size_t SurfaceMesh::capacity_bytes() const {
  return faces_.capacity() * sizeof(Triangle) + deleted_.capacity() + vattrs_.capacity_bytes() +
         fattrs_.capacity_bytes() + cattrs_.capacity_bytes();
}

VertexId SurfaceMesh::add_vertex(const glm::vec3& p) {
  const auto n = vattrs_.size();
  vattrs_.push_default(1);
  (*positions_)[n] = p;
  return VertexId(static_cast<std::uint32_t>(n));
}

namespace {
void check_face_vertices(VertexId a, VertexId b, VertexId c, std::size_t nv) {
  if (a.index >= nv || b.index >= nv || c.index >= nv)
    throw Error(ErrorCode::InvalidArgument, "add_face: vertex index out of range (" + std::to_string(a.index) + "," +
                                                std::to_string(b.index) + "," + std::to_string(c.index) + " of " +
                                                std::to_string(nv) + " vertices)");
}

// check_face_vertices over `count` faces: their largest index first (one pass without calls),
// the faces one by one only when it is out of range, so the first bad face is the one reported.
void check_faces_vertices(const Triangle* faces, std::size_t count, std::size_t nv) {
  std::uint32_t largest = 0;
  for (std::size_t i = 0; i < count; ++i)
    largest = std::max({largest, faces[i][0].index, faces[i][1].index, faces[i][2].index});
  if (count == 0 || largest < nv) return;
  for (std::size_t i = 0; i < count; ++i) check_face_vertices(faces[i][0], faces[i][1], faces[i][2], nv);
}
}  // namespace

FaceId SurfaceMesh::add_face(VertexId a, VertexId b, VertexId c) {
  const Triangle t = {a, b, c};
  return add_faces(&t, 1);
}

FaceId SurfaceMesh::add_faces(const Triangle* faces, std::size_t count) {
  const std::size_t nv = vertex_count();
  check_faces_vertices(faces, count, nv);
  const FaceId first(static_cast<std::uint32_t>(faces_.size()));
  faces_.insert(faces_.end(), faces, faces + count);
  deleted_.resize(deleted_.size() + count, 0);
  fattrs_.push_default(count);
  cattrs_.push_default(3 * count);
  return first;
}

FaceId SurfaceMesh::add_face_from(VertexId a, VertexId b, VertexId c, FaceId parent, const float* w) {
  check_face_vertices(a, b, c, vertex_count());
  faces_.push_back({a, b, c});
  deleted_.push_back(0);
  fattrs_.push_copy(parent.index);
  cattrs_.push_blend3(corner(parent, 0), w);
  return FaceId(static_cast<std::uint32_t>(faces_.size() - 1));
}

FaceId SurfaceMesh::add_faces_from(const Triangle* faces, const std::uint32_t* parents, const float* w,
                                   std::size_t count) {
  const std::size_t nv = vertex_count();
  check_faces_vertices(faces, count, nv);
  const FaceId first(static_cast<std::uint32_t>(faces_.size()));
  faces_.insert(faces_.end(), faces, faces + count);
  deleted_.resize(deleted_.size() + count, 0);
  fattrs_.push_copy_batch(parents, count);
  cattrs_.push_blend3_batch(parents, w, count);
  return first;
}

void SurfaceMesh::reserve(std::size_t vertices, std::size_t faces) {
  vattrs_.reserve(vertices);
  fattrs_.reserve(faces);
  cattrs_.reserve(3 * faces);
  faces_.reserve(faces);
  deleted_.reserve(faces);
}

void SurfaceMesh::mark_deleted(FaceId f) {
  if (!deleted_[f.index]) {
    if (observer_) observer_->face_writing(observer_id_, *this, f);
    deleted_[f.index] = 1;
    ++deleted_count_;
  }
}

void SurfaceMesh::assign(std::vector<Triangle> faces, AttributeSet vertex_attrs, AttributeSet face_attrs,
                         AttributeSet corner_attrs) {
  auto* positions = vertex_attrs.find<glm::vec3>(attr::kPosition);
  if (!positions) throw Error(ErrorCode::InvalidArgument, "SurfaceMesh::assign: no positions");
  if (face_attrs.size() != faces.size() || corner_attrs.size() != 3 * faces.size())
    throw Error(ErrorCode::InvalidArgument, "SurfaceMesh::assign: attribute sizes do not match the faces");
  for (const auto& t : faces)
    for (auto v : t)
      if (v.index >= vertex_attrs.size()) throw Error(ErrorCode::InvalidArgument, "SurfaceMesh::assign: vertex index out of range");
  assign_trusted(std::move(faces), std::move(vertex_attrs), std::move(face_attrs), std::move(corner_attrs));
}

void SurfaceMesh::assign_trusted(std::vector<Triangle> faces, AttributeSet vertex_attrs, AttributeSet face_attrs,
                                 AttributeSet corner_attrs) {
  if (observer_) release();
  faces_ = std::move(faces);
  deleted_.assign(faces_.size(), 0);
  deleted_count_ = 0;
  vattrs_ = std::move(vertex_attrs);
  fattrs_ = std::move(face_attrs);
  cattrs_ = std::move(corner_attrs);
  positions_ = vattrs_.find<glm::vec3>(attr::kPosition);
}

std::vector<std::uint32_t> SurfaceMesh::compact() {
  if (observer_) {
    MeshObserver* observer = observer_;
    observer_ = nullptr;
    observer->released(observer_id_, SurfaceMesh(*this));
  }
  std::vector<std::uint32_t> vmap(vertex_count(), kInvalidIndex);
  std::vector<std::uint32_t> keep_faces, keep_corners;
  keep_faces.reserve(face_count());
  keep_corners.reserve(3 * face_count());
  for (std::uint32_t f = 0; f < faces_.size(); ++f) {
    if (deleted_[f]) continue;
    keep_faces.push_back(f);
    for (int k = 0; k < 3; ++k) {
      keep_corners.push_back(3 * f + static_cast<std::uint32_t>(k));
      vmap[faces_[f][k].index] = 0;  // referenced
    }
  }
  // Keep vertex order stable: renumber in increasing old index, not first-use order.
  std::vector<std::uint32_t> sorted;
  for (std::uint32_t v = 0; v < vmap.size(); ++v)
    if (vmap[v] != kInvalidIndex) {
      vmap[v] = static_cast<std::uint32_t>(sorted.size());
      sorted.push_back(v);
    }
  std::vector<Triangle> faces;
  faces.reserve(keep_faces.size());
  for (std::uint32_t f : keep_faces) {
    const auto& t = faces_[f];
    faces.push_back({VertexId(vmap[t[0].index]), VertexId(vmap[t[1].index]), VertexId(vmap[t[2].index])});
  }
  faces_.swap(faces);
  deleted_.assign(faces_.size(), 0);
  deleted_count_ = 0;
  vattrs_.gather(sorted);
  fattrs_.gather(keep_faces);
  cattrs_.gather(keep_corners);
  return vmap;
}

BoundingBox SurfaceMesh::bounds() const {
  BoundingBox box;
  for_each_face([&](FaceId, const Triangle& t) {
    for (auto v : t) box.add(position(v));
  });
  return box;
}

double SurfaceMesh::area(const std::vector<glm::vec3>* positions) const {
  const auto& p = positions ? *positions : this->positions();
  double sum = 0.0;
  for_each_face([&](FaceId, const Triangle& t) {
    const glm::dvec3 a(p[t[0].index]), b(p[t[1].index]), c(p[t[2].index]);
    sum += 0.5 * glm::length(glm::cross(b - a, c - a));
  });
  return sum;
}

double SurfaceMesh::volume(const std::vector<glm::vec3>* positions) const {
  const auto& p = positions ? *positions : this->positions();
  double sum = 0.0;
  for_each_face([&](FaceId, const Triangle& t) {
    const glm::dvec3 a(p[t[0].index]), b(p[t[1].index]), c(p[t[2].index]);
    sum += glm::dot(a, glm::cross(b, c)) / 6.0;
  });
  return sum;
}

}  // namespace deepcut
