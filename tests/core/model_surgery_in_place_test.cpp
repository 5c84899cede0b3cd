// SPDX-License-Identifier: MIT
// The in-place moves of the mesh surgery (model_surgery_in_place): a piece compacted out of a
// mesh, then grown back and the rest scattered into it, on index lists long enough for every
// branch (a leading run that stays put, stretches copied in chunks at once, short ones copied in
// order, runs across the copy chunks' boundaries) and every copy width (fixed and any), gives
// byte for byte a plain serial gather and the mesh again, whatever the thread count.
#include "ops/common/model_surgery_in_place.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "deepcut/core/parallel.h"
#include "deepcut/core/process_memory.h"
#include "ops/common/model_surgery.h"

namespace deepcut::detail {
namespace {

std::uint32_t mix(std::uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  return static_cast<std::uint32_t>(x);
}

// An increasing list of indices below `count`, made of segments that hit every branch of the
// moves: a leading run that stays put, long runs after gaps wider than two copy chunks, every
// other index (short reaches), runs of 20000 that cross the 16384-group chunks, then a scatter.
std::vector<std::uint32_t> picks(std::size_t count, std::size_t gap) {
  std::vector<std::uint32_t> out;
  std::size_t i = 0;
  auto take = [&](std::size_t n, std::size_t stride) {
    for (std::size_t k = 0; k < n && i < count; ++k, i += stride) out.push_back(static_cast<std::uint32_t>(i));
  };
  take(1000, 1);
  i += gap;
  take(90000, 1);
  i += 3;
  take(20000, 2);
  for (int r = 0; r < 3; ++r) {
    i += 7 + static_cast<std::size_t>(r);
    take(20000, 1);
  }
  i += gap;
  take(40000, 1);
  for (; i < count; ++i)
    if (mix(i) % 10 < 7) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

std::vector<std::uint32_t> others(const std::vector<std::uint32_t>& keep, std::size_t count) {
  std::vector<char> kept(count, 0);
  for (std::uint32_t i : keep) kept[i] = 1;
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < count; ++i)
    if (!kept[i]) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

void fill(AttributeSet& set, std::uint64_t seed) {
  for (const std::string& name : set.names()) {
    AttributeArrayBase& array = *set.base(name);
    auto* bytes = static_cast<unsigned char*>(const_cast<void*>(array.element_data(0)));
    for (std::size_t b = 0; b < array.size() * array.element_bytes(); ++b)
      bytes[b] = static_cast<unsigned char>(mix(seed * 0x9e3779b97f4a7c15ULL + b));
  }
}

// Vertex widths 1, 8, 12, 64; face 1 and 12 (triangles); corners (3 per face) 3, 24, 48.
SurfaceMesh make_mesh(std::size_t nv, std::size_t nf, const std::vector<std::uint32_t>& kept_vertices) {
  AttributeSet v, f, c;
  v.add<glm::vec3>(attr::kPosition);
  v.add<std::uint8_t>("v:u8");
  v.add<glm::vec2>("v:vec2");
  v.add<glm::mat4>("v:mat4");
  f.add<std::uint8_t>("f:u8");
  c.add<std::uint8_t>("c:u8");
  c.add<glm::vec2>("c:vec2");
  c.add<glm::vec4>("c:vec4");
  v.resize(nv);
  f.resize(nf);
  c.resize(3 * nf);
  fill(v, 1);
  fill(f, 2);
  fill(c, 3);
  std::vector<Triangle> tris(nf);
  for (std::size_t i = 0; i < nf; ++i)
    for (std::uint32_t k = 0; k < 3; ++k)
      tris[i][k] = VertexId(kept_vertices[mix(3 * i + k) % kept_vertices.size()]);
  SurfaceMesh mesh;
  mesh.assign(std::move(tris), std::move(v), std::move(f), std::move(c));
  return mesh;
}

// Every array's bytes (name order) and the triangles.
std::string bytes_of(const SurfaceMesh& mesh) {
  std::string out;
  for (const AttributeSet* set : {&mesh.vertex_attrs(), &mesh.face_attrs(), &mesh.corner_attrs()})
    for (const std::string& name : set->names()) {
      const AttributeArrayBase& a = *set->base(name);
      out += name + ":" + std::to_string(a.size()) + ";";
      if (a.size()) out.append(static_cast<const char*>(a.element_data(0)), a.size() * a.element_bytes());
    }
  out.append(reinterpret_cast<const char*>(mesh.faces().data()), mesh.faces().size() * sizeof(Triangle));
  return out;
}

TEST(ModelSurgeryInPlaceTest, compact_then_expand_and_scatter_is_a_serial_gather_and_the_mesh_again) {
  const std::size_t nv = 320000, nf = 280000;
  const std::vector<std::uint32_t> vk = picks(nv, 40000), fk = picks(nf, 20000);
  const std::vector<std::uint32_t> vr = others(vk, nv), fr = others(fk, nf);
  ASSERT_GE(vk.size(), 200000u);
  ASSERT_GE(fk.size(), 200000u);
  const SurfaceMesh mesh = make_mesh(nv, nf, vk);
  std::vector<std::uint32_t> rank(nv, 0);
  for (std::size_t i = 0; i < vk.size(); ++i) rank[vk[i]] = static_cast<std::uint32_t>(i);

  // The serial reference: each array gathered element by element, triangles renumbered.
  std::vector<std::uint32_t> ck;
  for (std::uint32_t f : fk)
    for (std::uint32_t k = 0; k < 3; ++k) ck.push_back(3 * f + k);
  std::vector<Triangle> ref_tris;
  for (std::uint32_t f : fk) {
    Triangle t = mesh.faces()[f];
    for (VertexId& v : t) v = VertexId(rank[v.index]);
    ref_tris.push_back(t);
  }
  SurfaceMesh reference;
  reference.assign(std::move(ref_tris), mesh.vertex_attrs().subset(vk), mesh.face_attrs().subset(fk),
                   mesh.corner_attrs().subset(ck));
  const std::string want_piece = bytes_of(reference), want_whole = bytes_of(mesh);

  // What no piece holds, as the undo record keeps it.
  std::vector<std::uint32_t> cr;
  std::vector<Triangle> rest_tris;
  for (std::uint32_t f : fr) {
    for (std::uint32_t k = 0; k < 3; ++k) cr.push_back(3 * f + k);
    rest_tris.push_back(mesh.faces()[f]);
  }
  const AttributeSet rest[3] = {mesh.vertex_attrs().subset(vr), mesh.face_attrs().subset(fr),
                                mesh.corner_attrs().subset(cr)};
  const std::vector<Room> rooms = {{{&rest[0], &rest[1], &rest[2]}, rest_tris.data(), vr.size(), fr.size()}};
  const Elements from{{&rest[0], &rest[1], &rest[2]}, rest_tris.data(), nullptr, rest_tris.size()};

  const std::size_t saved = thread_count();
  for (std::size_t threads : {std::size_t{1}, std::size_t{2}, std::size_t{5}}) {
    SCOPED_TRACE(threads);
    set_thread_count(threads);
    SurfaceMesh piece = mesh;
    compact_piece(piece, plan_compaction(piece, vk, fk), vk, fk, rank.data());
    EXPECT_TRUE(bytes_of(piece) == want_piece);
    expand_piece(piece, vk, fk, nv, nf, rooms);
    scatter(piece, from, vr, fr);
    EXPECT_TRUE(bytes_of(piece) == want_whole);
    // Rooms that do not make up the growth (none given): grown by default values, same result.
    SurfaceMesh again = reference;
    expand_piece(again, vk, fk, nv, nf, {});
    scatter(again, from, vr, fr);
    EXPECT_TRUE(bytes_of(again) == want_whole);
  }
  set_thread_count(saved);
}

#if defined(__linux__)
// The whole pages inside [begin, end), and how many of them are resident (mincore).
struct Pages {
  std::size_t whole = 0, resident = 0;
};
Pages pages_in(const void* begin, const void* end) {
  const PageSpan span = inner_pages(begin, end);
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  Pages out;
  out.whole = (span.last - span.first) / page;
  if (out.whole == 0) return out;
  std::vector<unsigned char> in(out.whole);
  EXPECT_EQ(mincore(reinterpret_cast<void*>(span.first), span.last - span.first, in.data()), 0);
  for (unsigned char c : in) out.resident += c & 1;
  return out;
}

// A piece compacted in place keeps its mesh's capacity, but the pages of every array past the
// piece's room (split_room) (which held the mesh's other elements, all written) are handed
// back to the system: what stays resident follows the piece, not the mesh it was cut from. The
// room itself, what an operation on the piece grows into, stays resident.
TEST(ModelSurgeryInPlaceTest, a_compacted_piece_keeps_no_page_past_its_split_room_resident) {
  const std::size_t nv = 400000, nf = 360000;
  std::vector<std::uint32_t> vk(nv / 4), fk(nf / 4);
  for (std::size_t i = 0; i < vk.size(); ++i) vk[i] = static_cast<std::uint32_t>(4 * i);
  for (std::size_t i = 0; i < fk.size(); ++i) fk[i] = static_cast<std::uint32_t>(i + nf / 2);
  SurfaceMesh piece = make_mesh(nv, nf, vk);
  std::vector<std::uint32_t> rank(nv, 0);
  for (std::size_t i = 0; i < vk.size(); ++i) rank[vk[i]] = static_cast<std::uint32_t>(i);
  const std::size_t capacity = piece.capacity_bytes();
  compact_piece(piece, plan_compaction(piece, vk, fk), vk, fk, rank.data());
  EXPECT_EQ(piece.capacity_bytes(), capacity);
  const std::size_t rooms[3] = {split_room(vk.size()), split_room(fk.size()), 3 * split_room(fk.size())};
  for (int kind = 0; kind < 3; ++kind)
    for (const std::string& name : set_of(piece, kind).names()) {
      SCOPED_TRACE(name);
      const AttributeArrayBase& a = *set_of(piece, kind).base(name);
      const auto* data = static_cast<const unsigned char*>(a.element_data(0));
      const std::size_t size = a.size() * a.element_bytes(), room = rooms[kind] * a.element_bytes();
      ASSERT_GT(a.capacity_bytes(), room);
      EXPECT_EQ(pages_in(data + room, data + a.capacity_bytes()).resident, 0u);
      const Pages kept = pages_in(data + size, data + room);
      EXPECT_GT(kept.whole, 0u);
      EXPECT_EQ(kept.resident, kept.whole);
      EXPECT_GT(pages_in(data, data + size).resident, 0u);
    }
  const Triangle* tris = piece.faces().data();
  EXPECT_EQ(pages_in(tris + rooms[1], tris + piece.faces().capacity()).resident, 0u);
  EXPECT_EQ(pages_in(tris + piece.faces().size(), tris + rooms[1]).resident,
            pages_in(tris + piece.faces().size(), tris + rooms[1]).whole);
  const std::vector<std::uint8_t>& deleted = TrustedAssign::deleted(piece);
  ASSERT_EQ(deleted.size(), fk.size());
  EXPECT_EQ(pages_in(deleted.data() + rooms[1], deleted.data() + deleted.capacity()).resident, 0u);
}
#endif

}  // namespace
}  // namespace deepcut::detail
