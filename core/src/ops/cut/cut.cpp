// SPDX-License-Identifier: MIT
// The cut (ops/cut.h). Cutter::run states the stages:
//   1. classify_vertices: signed distance to the plane and snapped side of every vertex, at its
//      posed position;
//   2. split_crossed_faces: each crossed edge split once (ops/common/crossing_table.h, with the
//      needle merges) at the posed point where the plane crosses it, unposed to bind space
//      (ops/common/placement.h), each crossed face made again from up to three triangles
//      (crossings.cpp, planned there; the cut's state is in cutter.h);
//   3. separate_or_drop_side: the planned faces made, and rim vertices both sides use get a copy
//      for the positive side (its faces there made straight onto the copies), or the dropped
//      side's faces go;
//   4. pinch repair (ops/common/pinches.h), then the pieces: live faces by side (and component);
//   5. cap_pieces: each piece's rim, and with caps its cap (caps.cpp).
// cut_model runs cut_mesh on every instance through the instance loop of
// ops/common/model_surgery.h and turns the pieces into meshes and nodes.
#include "deepcut/core/ops/cut.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "ops/common/crossing_table.h"
#include "ops/common/model_surgery.h"
#include "ops/common/pinches.h"
#include "ops/common/placement.h"
#include "ops/common/posed_overlay.h"
#include "ops/cut/caps.h"
#include "ops/cut/classify.h"
#include "ops/cut/cutter.h"
#include "ops/cut/face_lists.h"
#include "side_by_side.h"
#include "uninit_vector.h"

namespace deepcut {
namespace {

// Side of a face: the side of its first corner off the plane (a face lying in the plane is
// positive), coded 1 positive, 2 negative.
inline std::uint8_t side_code(const std::int8_t* sign, const Triangle& t) {
  const int s0 = sign[t[0].index], s1 = sign[t[1].index], s2 = sign[t[2].index];
  const int s = s0 != 0 ? s0 : (s1 != 0 ? s1 : s2);
  return s < 0 ? 2 : 1;
}

// CutResult::vertex_sides from the cut's signs: a vertex on the plane gets the side of the live
// faces using it (rim candidates all, on one side each once the sides are apart). Writing a
// vertex's sign while later faces read it is safe for that reason: `separate_sides` has already
// given each on-plane vertex one side, so every face using it answers the same, before or after the write.
std::vector<std::int8_t> vertex_sides(const SurfaceMesh& mesh, std::vector<std::int8_t>&& sign,
                                      const std::vector<FaceId>& rim) {
  sign.resize(mesh.vertex_count(), 0);
  for (FaceId f : rim) {
    if (mesh.is_deleted(f)) continue;
    const Triangle& t = mesh.face(f);
    for (const VertexId v : t)
      if (sign[v.index] == 0) sign[v.index] = side_code(sign.data(), t) == 1 ? 1 : -1;
  }
  return std::move(sign);
}

}  // namespace

namespace detail {

// A test, true when vertex `v` is known to join its faces in one fan: a crossing vertex (or its copy)
// while no needle merged two crossings. Each face split_face makes around a crossing m on side
// s holds the piece (m, e) of the crossed edge whose end e is on side s, or shares an edge at m
// with a face that does; so each side's faces around m are joined through (m, e), and the
// copy takes all of the positive side's. The pinch split leaves such vertices alone.
auto Cutter::single_fans() const {
  return [merged = !merges_.empty(), c0 = crossings_[0], c1 = crossings_[1], d0 = crossing_copies_[0],
          d1 = crossing_copies_[1]](std::uint32_t v) {
    return !merged && ((v >= c0 && v < c1) || (v >= d0 && v < d1));
  };
}

// Rim vertices used by both sides get a copy for the positive side, so the sides come apart. The
// faces split_face planned are made here: the positive side's on a shared vertex straight onto
// the copies (move_positive_rim), the others first (make_planned), so no face is made only to
// be moved.
void Cutter::separate_sides() {
  // Per vertex on the plane: bit 1 a positive face uses it, bit 2 a negative one. The input's
  // vertices keep them in the scan's side bits (done with: bit 4 marks the vertices on the
  // plane, these go above it, at 8 and 16), the cut's in `fresh` (above them, for a vertex both
  // use, 1 + its place in `shared`): no array over the whole mesh is cleared. The faces: the
  // untouched ones on the plane (the rim candidates so far) and the planned ones.
  const std::uint32_t first_new = posed_.first_new();
  assert(side_bits_.size() == first_new);  // the input's vertices, each with its bits
  std::uint8_t* old_bits = side_bits_.data();
  std::vector<std::uint32_t> fresh(mesh_.vertex_count() - first_new, 0);
  std::vector<std::uint32_t> touched;  // the input's, each once
  const std::int8_t* sign = sign_.data();
  auto mark = [&](const Triangle& t) {
    const std::uint8_t bit = side_code(sign, t);
    for (auto v : t) {
      if (sign[v.index] != 0) continue;
      if (v.index >= first_new) {
        fresh[v.index - first_new] |= bit;
        continue;
      }
      if ((old_bits[v.index] & 24) == 0) touched.push_back(v.index);
      old_bits[v.index] |= static_cast<std::uint8_t>(bit << 3);
    }
  };
  const std::size_t touching = rim_candidates_.size();
  for (FaceId f : rim_candidates_)
    if (!mesh_.is_deleted(f)) mark(mesh_.face(f));
  for (const Planned& p : planned_) mark(p.t);
  // In id order (deterministic vertex numbering): the input's vertices sorted, then the cut's
  // (the newest ids) as they come.
  std::vector<std::uint32_t> shared;
  for (std::uint32_t v : touched)
    if ((old_bits[v] & 24) == 24) shared.push_back(v);
  std::sort(shared.begin(), shared.end());
  const std::size_t old_shared = shared.size();
  for (std::size_t i = 0; i < fresh.size(); ++i)
    if (fresh[i] == 3) {
      shared.push_back(first_new + static_cast<std::uint32_t>(i));
      fresh[i] |= static_cast<std::uint32_t>(shared.size()) << 2;
    }
  if (shared.empty()) return make_planned(nullptr);
  // The copies come next (the planned faces add no vertex): the positive side's planned faces on
  // a shared vertex wait for them.
  const SharedSlots slots{shared, old_shared, fresh};
  const auto first_copy = static_cast<std::uint32_t>(mesh_.vertex_count());
  // Each planned face to be moved is flagged and put on the copies at once.
  std::vector<std::uint8_t> moved(planned_.size(), 0);
  Triangle on_copies;
  for (std::size_t i = 0; i < planned_.size(); ++i)
    if (moved_face(planned_[i].t, slots, first_copy, on_copies)) {
      moved[i] = 1;
      planned_[i].t = on_copies;
    }
  make_planned(&moved);
  [[maybe_unused]] const VertexId copy = editor_.split_vertices(shared.data(), shared.size());
  assert(copy.index == first_copy);
  for (const std::uint32_t v : shared) {
    posed_.add(posed_(VertexId(v)));
    dist_.push_back(dist_[v]);
    sign_.push_back(0);
  }
  // shared is sorted and the crossings are the newest vertices: their copies come last.
  const auto first_of_crossing =
      static_cast<std::size_t>(std::lower_bound(shared.begin(), shared.end(), crossings_[0]) - shared.begin());
  if (first_of_crossing < shared.size()) {
    crossing_copies_[0] = first_copy + static_cast<std::uint32_t>(first_of_crossing);
    crossing_copies_[1] = first_copy + static_cast<std::uint32_t>(shared.size());
  }
  move_positive_rim(touching, moved, slots, VertexId(first_copy));
}

// The place in `shared` of vertex `v` on the plane (the input's first `old_shared` of them
// sorted; `fresh` and the side bits as separate_sides left them), or kInvalidIndex.
std::uint32_t Cutter::SharedSlots::slot(std::uint32_t v, std::uint32_t first_new, const std::uint8_t* old_bits) const {
  static_assert(kInvalidIndex == std::uint32_t(0) - 1, "an unshared new vertex's slot, 0 - 1, reads as none");
  if (v >= first_new) return (fresh[v - first_new] >> 2) - 1;  // not shared: 0 - 1, kInvalidIndex
  if ((old_bits[v] & 24) != 24) return kInvalidIndex;
  const auto old_end = shared.begin() + static_cast<std::ptrdiff_t>(old_shared);  // few: searched
  return static_cast<std::uint32_t>(std::lower_bound(shared.begin(), old_end, v) - shared.begin());
}

// True when `t` is a positive face using a shared vertex: `moved` is `t` on the copies (the copy
// of shared[i] is first_copy + i).
bool Cutter::moved_face(const Triangle& t, const SharedSlots& slots, std::uint32_t first_copy, Triangle& moved) const {
  const std::int8_t* sign = sign_.data();
  if (side_code(sign, t) == 2) return false;
  const std::uint32_t first_new = posed_.first_new();
  moved = t;
  bool changed = false;
  for (auto& v : moved) {
    if (sign[v.index] != 0) continue;
    const std::uint32_t slot = slots.slot(v.index, first_new, side_bits_.data());
    if (slot == kInvalidIndex) continue;
    v = VertexId(first_copy + slot);
    changed = true;
  }
  return changed;
}

// Moves the positive side's rim faces onto the copies of their shared vertices, in one batch: the
// untouched faces on the plane (the first `touching` rim candidates) removed and made again, then
// the planned faces `moved_planned` flags (already on the copies) made there at once.
void Cutter::move_positive_rim(std::size_t touching, const std::vector<std::uint8_t>& moved_planned,
                               const SharedSlots& slots, VertexId first_copy) {
  const auto first_new_face = static_cast<std::uint32_t>(mesh_.face_slots());
  const glm::vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  FaceBatch batch;
  batch.reserve(touching + planned_.size(), touching);
  Triangle moved;
  for (std::size_t i = 0; i < touching; ++i) {
    const FaceId f = rim_candidates_[i];
    if (mesh_.is_deleted(f) || !moved_face(mesh_.face(f), slots, first_copy.index, moved)) continue;
    batch.remove(f);
    batch.add_from(moved, f, {e[0], e[1], e[2]});
  }
  for (std::size_t i = 0; i < planned_.size(); ++i) {
    if (moved_planned[i]) batch.add_moved_from(planned_[i].t, planned_[i].parent, planned_[i].bary);
  }
  editor_.apply(batch);
  detail::append_run(rim_candidates_, first_new_face, static_cast<std::uint32_t>(mesh_.face_slots()));
}

// A rim through a vertex on the plane (a saddle, or a fold touching the plane within the
// tolerance) can leave that vertex joining two fans of one side's faces that meet only there, and
// a cap over a rim that touches itself can too: each fan gets its own vertex. Every face using an
// on-plane vertex is a rim candidate or a cap face. The first `candidates` rim candidates are
// looked at: the ones after them (the cap faces) must have every corner on the plane one fan.
// With `result`, its pieces follow the faces moved onto copies.
template <class OneFan>
std::vector<std::pair<VertexId, VertexId>> Cutter::split_pinches(CutResult* result, const OneFan& one_fan,
                                                                 std::size_t candidates) {
  // The vertices listed as often as faces use them, then sorted and made unique: a flag per
  // vertex of the mesh would be an array of the whole mesh to clear for the few on the plane.
  std::vector<VertexId> on_plane;
  std::vector<FaceId> incident;  // the live rim candidates using one of them
  // What the loop reads, held locally: else the pushes, which might write anywhere, make the
  // compiler read each member again for every face.
  const OneFan fan = one_fan;
  const FaceId* candidate = rim_candidates_.data();
  const Triangle* faces = mesh_.faces().data();
  const std::int8_t* sign = sign_.data();
  for (std::size_t k = 0; k < candidates; ++k) {
    const FaceId f = candidate[k];
    if (mesh_.is_deleted(f)) continue;
    bool uses = false;
    for (const VertexId v : faces[f.index]) {
      if (sign[v.index] != 0 || fan(v.index)) continue;
      uses = true;
      on_plane.push_back(v);
    }
    if (uses) incident.push_back(f);
  }
  if (on_plane.empty()) return {};
  std::sort(on_plane.begin(), on_plane.end());
  on_plane.erase(std::unique(on_plane.begin(), on_plane.end()), on_plane.end());
  const std::size_t before = mesh_.face_slots();
  const auto splits = detail::split_pinched_vertices(editor_, on_plane, incident);
  for (const auto& [v, c] : splits.copies) {
    (void)c;
    posed_.add(posed_(v));
    dist_.push_back(dist_[v.index]);
    sign_.push_back(0);
  }
  detail::append_run(rim_candidates_, static_cast<std::uint32_t>(before),
                     static_cast<std::uint32_t>(mesh_.face_slots()));
  if (!result || splits.replaced.empty()) return splits.copies;
  std::vector<std::pair<FaceId, FaceId>> moved = splits.replaced;  // each old face once
  std::sort(moved.begin(), moved.end());
  for (auto& piece : result->pieces) follow_moved_faces(moved, FaceId(static_cast<std::uint32_t>(before)), piece);
  return splits.copies;
}

namespace {

// More cap faces than this at one vertex: left to the pinch split.
constexpr std::uint32_t kMaxCapFan = 32;

// The flags of capped_single_fans over the vertices [lo, lo + n) from the cap faces [first_cap_face,
// end of the mesh) and the pieces' rim halfedges, `first` counting each vertex's cap faces at first[v - lo
// + 1]. A vertex's cap faces as bits (face i of its list: bit i): those sharing an edge at the
// vertex with each face (a corner besides it), and those along a rim edge; the faces reached from
// the latter through the former must be all of them. False for a degenerate cap face.
bool fans_reach_rim(const SurfaceMesh& mesh, std::uint32_t first_cap_face, const std::vector<CapInput>& rims,
                    std::uint32_t lo, std::vector<std::uint32_t>& first, std::vector<std::uint8_t>& flags) {
  const std::size_t n = first.size() - 1;
  const auto end_face = static_cast<std::uint32_t>(mesh.face_slots());
  auto in_range = [&](VertexId v) { return v.index >= lo && v.index - lo < n; };
  auto each_rim_edge = [&](auto&& fn) {
    for (const CapInput& in : rims)
      for (const auto& [a, b] : *in.rim) fn(a, b);
  };
  std::vector<std::uint32_t> rim_first(n + 1, 0);
  each_rim_edge([&](VertexId a, VertexId b) {
    if (in_range(a)) ++rim_first[a.index - lo + 1];
    if (in_range(b)) ++rim_first[b.index - lo + 1];
  });
  for (std::size_t i = 0; i < n; ++i) {
    first[i + 1] += first[i];
    rim_first[i + 1] += rim_first[i];
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> others(first[n]);
  std::vector<std::uint32_t> rim_next(rim_first[n]);
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1), rim_fill(rim_first.begin(), rim_first.end() - 1);
    for (auto f = first_cap_face; f < end_face; ++f) {
      const Triangle& t = mesh.face(FaceId(f));
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;  // a degenerate cap: no shortcut
      for (int k = 0; k < 3; ++k)
        if (in_range(t[k])) others[fill[t[k].index - lo]++] = {t[(k + 1) % 3].index, t[(k + 2) % 3].index};
    }
    each_rim_edge([&](VertexId a, VertexId b) {
      if (in_range(a)) rim_next[rim_fill[a.index - lo]++] = b.index;
      if (in_range(b)) rim_next[rim_fill[b.index - lo]++] = a.index;
    });
  }
  flags.assign(n, 0);
  std::uint32_t shares[kMaxCapFan];
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint32_t m = first[v + 1] - first[v];
    if (m == 0 || m > kMaxCapFan) continue;
    const auto* c = others.data() + first[v];
    const std::uint32_t* nb = rim_next.data() + rim_first[v];
    const std::uint32_t* nb_end = rim_next.data() + rim_first[v + 1];
    std::uint32_t reached = 0;
    for (std::uint32_t i = 0; i < m; ++i) {
      shares[i] = 0;
      for (const std::uint32_t* x = nb; x != nb_end; ++x)
        if (c[i].first == *x || c[i].second == *x) reached |= 1u << i;
    }
    for (std::uint32_t i = 0; i < m; ++i)
      for (std::uint32_t j = i + 1; j < m; ++j)
        if (c[i].first == c[j].first || c[i].first == c[j].second || c[i].second == c[j].first ||
            c[i].second == c[j].second) {
          shares[i] |= 1u << j;
          shares[j] |= 1u << i;
        }
    for (std::uint32_t grown = reached; grown;) {  // the faces newly reached, until none
      std::uint32_t next = 0;
      for (std::uint32_t i = 0; i < m; ++i)
        if (grown >> i & 1u) next |= shares[i];
      grown = next & ~reached;
      reached |= grown;
    }
    flags[v] = reached == (m == 32 ? ~0u : (1u << m) - 1) ? 1 : 0;
  }
  return true;
}

}  // namespace

// Flags over the rim vertices [first, first + size): 1 where the vertex's faces are still one fan
// with the caps added. Every cap face there reaches, through cap faces sharing an edge there, a
// cap face along one of the piece's rim edges (`rims`: the pieces' rim halfedges), which is an edge of the
// vertex's one fan of piece faces (the first pinch split left one; no face of it was removed).
// With `whole_fans` (make_caps) every cap face at a vertex is in a fan from one of its rim edges
// to another, so a vertex with cap faces (not too many) is flagged without looking at them.
Cutter::VertexFlags Cutter::capped_single_fans(std::uint32_t first_cap_face,
                                               const std::vector<detail::CapInput>& rims,
                                               bool whole_fans) const {
  VertexFlags out;
  const auto end_face = static_cast<std::uint32_t>(mesh_.face_slots());
  // Only the vertices the cut made, [lo, hi] (the input's on the rim are few: the pinch split
  // looks at them), so the arrays below follow the edit, not the mesh.
  const std::uint32_t lo = posed_.first_new();
  if (mesh_.vertex_count() <= lo) return out;
  const auto hi = static_cast<std::uint32_t>(mesh_.vertex_count() - 1);
  // Cap faces by vertex, counted at first[v - lo + 1].
  const std::size_t n = hi - lo + 1;
  std::vector<std::uint32_t> first(n + 1, 0);
  std::size_t outside = 0;  // cap corners before lo
  for (auto f = first_cap_face; f < end_face; ++f)
    for (const VertexId v : mesh_.face(FaceId(f))) {
      if (v.index >= lo && v.index <= hi)
        ++first[v.index - lo + 1];
      else
        ++outside;
    }
  if (whole_fans) {
    out.flags.resize(n);
    bool crowded = false;  // a vertex with more cap faces than kMaxCapFan
    for (std::size_t v = 0; v < n; ++v) {
      out.flags[v] = first[v + 1] != 0 && first[v + 1] <= kMaxCapFan;
      crowded = crowded || first[v + 1] > kMaxCapFan;
    }
    out.cap_corners = outside == 0 && !crowded;
  } else if (!fans_reach_rim(mesh_, first_cap_face, rims, lo, first, out.flags)) {
    return out;
  }
  out.first = lo;
  return out;
}

// The rim faces of each piece (faces with two or more corners on the plane: the only ones that
// can have rim edges), in face order, as the caps take them.
std::vector<detail::CapInput> Cutter::rim_of_pieces(const CutResult& result) const {
  std::vector<detail::CapInput> rims(result.pieces.size());
  for (detail::CapInput& rim : rims) {
    rim.normal = normal_;
    rim.point = point_;
    rim.posed = &posed_;
    rim.sign = &sign_;
  }
  // Piece of each face: by face slot when components were split, else by side.
  std::vector<std::uint32_t> piece_of_face;
  std::uint32_t piece_of_side[2] = {kInvalidIndex, kInvalidIndex};
  if (options_.split_components) {
    piece_of_face.assign(mesh_.face_slots(), kInvalidIndex);
    for (std::size_t p = 0; p < result.pieces.size(); ++p)
      for (FaceId f : result.pieces[p]) piece_of_face[f.index] = static_cast<std::uint32_t>(p);
  } else {
    for (std::size_t p = 0; p < result.pieces.size(); ++p)
      piece_of_side[result.piece_sides[p] > 0 ? 0 : 1] = static_cast<std::uint32_t>(p);
  }
  // Room for every candidate in each of two pieces (more pieces grow their lists as they go).
  if (rims.size() <= 2)
    for (detail::CapInput& rim : rims) rim.rim_faces.reserve(rim_candidates_.size());
  const std::int8_t* sign = sign_.data();  // locals: the pushes would make members be read again
  const Triangle* faces = mesh_.faces().data();
  const bool split = options_.split_components;
  for (FaceId f : rim_candidates_) {
    if (mesh_.is_deleted(f)) continue;
    const Triangle t = faces[f.index];
    const int zeros = (sign[t[0].index] == 0) + (sign[t[1].index] == 0) + (sign[t[2].index] == 0);
    if (zeros < 2) continue;
    const std::uint32_t p = split ? piece_of_face[f.index] : piece_of_side[side_code(sign, t) - 1];
    if (p != kInvalidIndex) rims[p].rim_faces.push_back(f);
  }
  return rims;
}

void Cutter::collect_pieces(CutResult& result) {
  // Live faces by side, in id order: the untouched ones off the plane (listed by the scan, no
  // edit removes them) merged with the live rim candidates (ascending: the scan's touching
  // faces, then every face the cut made).
  std::vector<FaceId> rim[2], side_faces[2];
  live_rim_by_side(rim);
  live_side_faces({true, true}, rim, side_faces);
  for (int s = 0; s < 2; ++s) {
    if (side_faces[s].empty()) continue;
    const int side = s == 0 ? 1 : -1;
    if (!options_.split_components) {
      result.pieces.push_back(std::move(side_faces[s]));
      result.piece_sides.push_back(side);
      continue;
    }
    std::vector<std::uint32_t> parent(mesh_.vertex_count());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (FaceId f : side_faces[s]) {
      const auto& t = mesh_.face(f);
      for (int k = 1; k < 3; ++k) {
        const auto a = root(t[0].index), b = root(t[k].index);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    std::unordered_map<std::uint32_t, std::size_t> piece_of;
    for (FaceId f : side_faces[s]) {
      const auto r = root(mesh_.face(f)[0].index);
      auto [it, inserted] = piece_of.emplace(r, result.pieces.size());
      if (inserted) {
        result.pieces.emplace_back();
        result.piece_sides.push_back(side);
      }
      result.pieces[it->second].push_back(f);
    }
  }
}

void Cutter::check_arguments() const {
  const std::size_t nv = mesh_.vertex_count();
  if (posed_.input().size() != nv)
    throw Error(ErrorCode::InvalidArgument, "cut: " + std::to_string(posed_.input().size()) + " posed positions for " +
                                                std::to_string(nv) + " vertices");
  check_cut_plane({glm::vec3(point_), glm::vec3(normal_)});
}

// Classifies every vertex (ops/cut/classify.h): the vertices `used` flags count, or all.
void Cutter::classify_vertices(const std::uint8_t* used) {
  const std::size_t nv = mesh_.vertex_count();
  // Room for the vertices the cut adds (crossings, their copies: a few per crossed face, far
  // fewer than the mesh's), so appending them in make_crossings does not copy the arrays.
  detail::VertexSides sides =
      detail::classify_vertices(mesh_, posed_.input(), glm::vec3(point_), glm::vec3(normal_),
                                options_.relative_tolerance, nv + nv / 16 + 256, used);
  dist_ = std::move(sides.dist);
  sign_ = std::move(sides.sign);
  side_bits_ = std::move(sides.bits);
  both_sides_ = sides.both_sides;
}

// Classifies every vertex and scans the faces (found_): the faces the plane crosses, the
// untouched faces with a corner on the plane (rim candidates) and the untouched faces off it by
// side (the bulk of the pieces: no edit changes them). False when every vertex lies on one side.
// A vertex no face uses counts for neither side: the classification first takes every vertex
// as used, and the scan, one pass over the faces, checks it (a mesh as loaded or compacted uses
// every vertex); else both are made again knowing the unused ones.
bool Cutter::classify_and_scan() {
  const std::size_t nv = mesh_.vertex_count();
  // Not value-initialised (new[] without ()): clear_flags zeroes the bytes over the pool, where
  // value-initialising would zero them first on the calling thread (2M at 4M triangles).
  std::unique_ptr<std::uint8_t[]> used(new std::uint8_t[nv]);
  detail::clear_flags(used.get(), nv);
  classify_vertices(nullptr);
  if (both_sides_)
    found_ = detail::scan_faces(mesh_, side_bits_.data(), used.get());
  else
    detail::flag_used(mesh_, used.get());
  if (detail::all_flagged(used.get(), nv)) return both_sides_;
  classify_vertices(used.get());
  if (!both_sides_) return false;
  found_ = detail::scan_faces(mesh_, side_bits_.data(), nullptr);
  return true;
}

// Makes the crossings of the faces the scan found crossed and plans the faces replacing those
// (separate_or_drop_side makes them), and files the scan's other faces.
void Cutter::split_crossed_faces() {
  // Room for the faces the cut makes and the caps (a few per crossed or touching face), which
  // join the pieces later: growing a list of most of the mesh would copy it.
  std::size_t rim_faces = 0;
  for (const detail::ScannedFaces& part : found_) rim_faces += part.crossed.size() + part.touching.size();
  side_room_ = 8 * rim_faces + 64;
  // One chunk (one thread, a small mesh) holds the sides' lists themselves: their room is made now.
  if (found_.size() == 1)
    for (std::vector<FaceId>& list : found_[0].clean) list.reserve(list.size() + side_room_);
  std::size_t crossed = 0;
  for (const detail::ScannedFaces& part : found_) crossed += part.crossed.size();
  splits_.reserve(2 * crossed);  // about one new crossed edge per crossed face, two at most
  rim_candidates_.reserve(8 * rim_faces + 64);  // the touching faces, the faces the cut makes
  // Per crossed face about: a crossing, its removal, three faces, and separating the sides a
  // copy (and a few untouched faces moved: a removal and an addition each).
  editor_.reserve_log(10 * crossed);
  crossings_[0] = static_cast<std::uint32_t>(mesh_.vertex_count());
  merge_candidates_.reserve(crossed);
  face_crossings_.reserve(2 * crossed);
  for (const detail::ScannedFaces& part : found_)
    for (FaceId f : part.crossed) split_crossings(f);
  make_crossings();
  crossings_[1] = static_cast<std::uint32_t>(mesh_.vertex_count());
  planned_.reserve(3 * crossed);
  crossed_.reserve(crossed);
  std::size_t face = 0;
  for (const detail::ScannedFaces& part : found_) {
    for (FaceId f : part.crossed) split_face(f, &face_crossings_[2 * face++]);
    rim_candidates_.insert(rim_candidates_.end(), part.touching.begin(), part.touching.end());
  }
  // Only the chunks' untouched faces are read later (live_side_faces): the rest goes now.
  for (detail::ScannedFaces& part : found_) {
    std::vector<FaceId>().swap(part.crossed);
    std::vector<FaceId>().swap(part.touching);
  }
}

void Cutter::separate_or_drop_side() {
  if (options_.keep == CutKeep::Both) {
    separate_sides();
  } else {
    make_planned(nullptr);
    // Every live face of the dropped side, in id order.
    const int drop = options_.keep == CutKeep::Positive ? 1 : 0;
    std::vector<FaceId> rim[2], doomed[2];
    live_rim_by_side(rim);
    live_side_faces({drop == 0, drop == 1}, rim, doomed);
    for (FaceId f : doomed[drop]) editor_.remove_face(f);
  }
}

// The live rim candidates by side (positive, negative), in id order.
void Cutter::live_rim_by_side(std::vector<FaceId> (&out)[2]) const {
  // Room for every candidate on each side (a few thousand ids at most), so neither list grows.
  out[0].reserve(out[0].size() + rim_candidates_.size());
  out[1].reserve(out[1].size() + rim_candidates_.size());
  const std::int8_t* sign = sign_.data();
  const Triangle* faces = mesh_.faces().data();
  for (FaceId f : rim_candidates_)
    if (!mesh_.is_deleted(f)) out[side_code(sign, faces[f.index]) - 1].push_back(f);
}

// The live faces of each side `want`s (0 positive, 1 negative) in id order, into `out` by side:
// the side's untouched faces off the plane (the scan's chunks, taken: a second call gives the rim
// alone) merged with its live rim candidates `rim[side]` (ascending), with side_room_ to grow.
// From several chunks, each chunk is merged with the rim faces in its range of ids into its own
// part of the list, the parts side by side; the newer rim faces come last. Each list's room is
// reserved on the calling thread (its heap), then the lists are sized side by side, a list a
// task (size_side_by_side): a list's growth fills every entry with an invalid id first (a
// result's piece is a std::vector<FaceId>, whose growth value-initialises), about 0.4-0.7 ms a
// side of a 4M-triangle cut (2M ids) where the memory is reused, 15-65 ms where its pages are
// fresh (faulted in by the fill); the sides' fills run in parallel, each one serial within its
// task. Then every side's parts are merged in one job. Both sides' lists are allocated while
// every chunk's lists are still alive (each chunk's are freed as it is merged): at the peak the
// faces off the plane are held twice, in the chunks and in the sides' lists, about 8 MB more at
// 4M triangles than sizing and merging one side after the other.
void Cutter::live_side_faces(const bool (&want)[2], const std::vector<FaceId> (&rim)[2],
                             std::vector<FaceId> (&out)[2]) {
  int sides[2];  // the wanted sides, each once
  std::size_t count = 0;
  for (int s = 0; s < 2; ++s)
    if (want[s]) sides[count++] = s;
  const std::size_t n = found_.size();
  if (n <= 1) {
    for (std::size_t i = 0; i < count; ++i) {
      const int side = sides[i];
      out[side] = n == 0 ? std::vector<FaceId>() : std::move(found_[0].clean[side]);  // leaves it empty
      merge_sorted(out[side], rim[side]);
    }
    return;
  }
  // Side i's chunk c has the rim faces rim[first_rim[i][c], first_rim[i][c + 1]), its part starts
  // at at[i][c]; past at[i][n] come the newer rim faces.
  std::vector<std::vector<std::size_t>> first_rim(count, std::vector<std::size_t>(n + 1, 0)), at = first_rim;
  for (std::size_t i = 0; i < count; ++i) {
    const std::vector<FaceId>& r = rim[sides[i]];
    for (std::size_t c = 0; c < n; ++c) {
      first_rim[i][c + 1] =
          static_cast<std::size_t>(std::lower_bound(r.begin(), r.end(), FaceId(found_[c].end)) - r.begin());
      at[i][c + 1] = at[i][c] + found_[c].clean[sides[i]].size() + (first_rim[i][c + 1] - first_rim[i][c]);
    }
    out[sides[i]] = std::vector<FaceId>();
  }
  detail::size_side_by_side(
      count, [&](std::size_t i) -> std::vector<FaceId>& { return out[sides[i]]; },
      [&](std::size_t i) { return at[i][n] + (rim[sides[i]].size() - first_rim[i][n]); }, side_room_);
  detail::run_chunks(count * (n + 1), [&](std::size_t k) {
    const std::size_t i = k / (n + 1), c = k % (n + 1);
    const int side = sides[i];
    const FaceId* r = rim[side].data();
    FaceId* to = out[side].data();
    if (c == n) {
      std::copy(r + first_rim[i][n], r + rim[side].size(), to + at[i][n]);
      return;
    }
    std::vector<FaceId>& chunk = found_[c].clean[side];
    std::merge(chunk.begin(), chunk.end(), r + first_rim[i][c], r + first_rim[i][c + 1], to + at[i][c]);
    std::vector<FaceId>().swap(chunk);
  });
}

// Rim vertices (on the plane, bounding a piece) into `rim`, sorted and unique; with caps, each
// piece capped.
void Cutter::cap_pieces(CutResult& result, std::vector<VertexId>& rim) {
  std::vector<detail::CapInput> rims = rim_of_pieces(result);
  // The input's rim vertices sorted, then the cut's (the newest ids) by a flag each.
  const std::uint32_t first_new = posed_.first_new();
  std::vector<std::uint8_t> on_rim(mesh_.vertex_count() - first_new, 0);
  std::size_t halfedges = 0;
  for (detail::CapInput& in : rims) {
    in.rim = detail::rim_halfedges(mesh_, in);  // the cap takes it too
    halfedges += in.rim->size();
  }
  rim.reserve(halfedges);  // each rim vertex ends a rim halfedge
  for (const detail::CapInput& in : rims) {
    for (const auto& [a, b] : *in.rim) {
      for (const VertexId v : {a, b}) {
        if (v.index >= first_new)
          on_rim[v.index - first_new] = 1;
        else
          rim.push_back(v);
      }
    }
  }
  std::sort(rim.begin(), rim.end());
  rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
  for (std::size_t i = 0; i < on_rim.size(); ++i)
    if (on_rim[i]) rim.push_back(VertexId(first_new + static_cast<std::uint32_t>(i)));
  if (!options_.cap) return;
  const auto first_cap_face = static_cast<std::uint32_t>(mesh_.face_slots());
  const std::size_t live_before = mesh_.face_count();
  const std::size_t uncapped = rim_candidates_.size();
  const bool whole_fans = detail::make_caps(editor_, rims, result.pieces);
  detail::append_run(rim_candidates_, first_cap_face, static_cast<std::uint32_t>(mesh_.face_slots()));
  // With a face of a piece removed (a flat one the cap replaced) its fans may have come apart:
  // then every rim vertex is looked at.
  VertexFlags one_fan;
  if (mesh_.face_count() - live_before == mesh_.face_slots() - first_cap_face)
    one_fan = capped_single_fans(first_cap_face, rims, whole_fans);
  const std::size_t before = rim.size();
  // The cap faces (the last rim candidates) are left out where every corner of theirs is one fan.
  const std::size_t candidates = one_fan.cap_corners ? uncapped : rim_candidates_.size();
  for (const auto& [v, c] : split_pinches(&result, one_fan.test(), candidates))
    if (std::binary_search(rim.begin(), rim.begin() + static_cast<std::ptrdiff_t>(before), v)) rim.push_back(c);
  if (rim.size() > before) std::sort(rim.begin(), rim.end());  // rim[0, before) is sorted already
}

CutResult Cutter::run() {
  CutResult result;
  check_arguments();
  normal_ /= glm::length(normal_);
  const bool had_deleted = mesh_.face_count() != mesh_.face_slots();  // their vertices get a sign too
  if (!classify_and_scan()) {
    result.status = OpStatus::NoIntersection;
    return result;
  }
  split_crossed_faces();
  separate_or_drop_side();
  split_pinches(nullptr, single_fans(), rim_candidates_.size());
  collect_pieces(result);
  cap_pieces(result, result.rim_vertices);
  if (!options_.cap && !options_.split_components && merges_.empty() && !had_deleted)
    detail::CutSides::of(result) = vertex_sides(mesh_, std::move(sign_), rim_candidates_);
  result.intersection_points = intersections_;
  result.log = editor_.take_log();
  return result;
}

}  // namespace detail

void check_cut_plane(const Plane& plane) {
  const double nlen = glm::length(glm::dvec3(plane.normal));
  if (nlen == 0.0) throw Error(ErrorCode::InvalidArgument, "cut: the plane normal is zero");
  if (!std::isfinite(nlen)) throw Error(ErrorCode::InvalidArgument, "cut: the plane normal is not finite");
  if (!std::isfinite(plane.point.x) || !std::isfinite(plane.point.y) || !std::isfinite(plane.point.z))
    throw Error(ErrorCode::InvalidArgument, "cut: the plane point is not finite");
}

CutResult cut_mesh(SurfaceMesh& mesh, PosedMesh& posed, const Plane& plane, const CutOptions& options) {
  detail::Cutter cutter(mesh, posed.posed, plane, options, detail::Placement(posed, mesh));
  CutResult result = cutter.run();
  posed.follow(mesh, result.log);
  return result;
}

CutResult cut_mesh(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const Plane& plane, const CutOptions& options) {
  return detail::Cutter(mesh, posed, plane, options).run();
}

}  // namespace deepcut
