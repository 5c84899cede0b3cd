// SPDX-License-Identifier: MIT
// The cut's crossings (ops/cut/cutter.h): each crossed edge split once, at the posed point where
// the plane crosses it, in one editor batch; each crossed face made again from up to three
// triangles around its crossings.
#include <cassert>
#include <cstdint>
#include <vector>

#include "ops/cut/cutter.h"

namespace deepcut::detail {

// The crossing of edge {a, b}: on the first call for the edge, its record with the id of the
// vertex make_crossings makes there later (the crossings' vertices come in the order of their
// edges' first calls, from crossings_[0] on). The id is handed out before the vertex exists, so
// it holds only while no vertex is added between setting crossings_[0] and make_crossings.
const Cutter::Split& Cutter::split_edge(VertexId a, VertexId b) {
  assert(mesh_.vertex_count() == crossings_[0]);  // no vertex made since the ids were counted
  const auto [s, made] = splits_.try_emplace(a, b);
  if (!made) return *s;
  const VertexId lo = a < b ? a : b, hi = a < b ? b : a;
  const double dl = dist_[lo.index], dh = dist_[hi.index];
  const float t = static_cast<float>(dl / (dl - dh));
  *s = Split{lo, hi, VertexId(crossings_[0] + static_cast<std::uint32_t>(splits_.size() - 1)), t};
  return *s;
}

// Makes the vertices of the crossings split_crossings found, in one editor batch, each placed
// at its posed crossing point; then merges the needles' crossings that came out near.
void Cutter::make_crossings() {
  const std::size_t n = splits_.size();
  std::vector<std::uint32_t> ends(2 * n);
  std::vector<float> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    ends[2 * i] = splits_[i].lo.index;
    ends[2 * i + 1] = splits_[i].hi.index;
    t[i] = splits_[i].t;
  }
  [[maybe_unused]] const VertexId first = editor_.add_vertices_on_edges(ends.data(), t.data(), n);
  assert(first.index == crossings_[0]);  // the ids split_edge handed out
  // The crossings' VertexAdded entries all come first, then their VertexMoved ones (edit_log.h),
  // placing each as it is made or all of them after the loop alike: many crossings to unpose are
  // placed after it, side by side (Placement::place_all).
  const bool side_by_side = placement_.unposes() && n > Placement::kPlaceGrain;
  std::vector<VertexId> ids;
  std::vector<glm::vec3> targets;
  if (side_by_side) {
    ids.reserve(n);
    targets.reserve(n);
  }
  for (const Split& s : splits_) {
    const glm::vec3 at = glm::mix(posed_(s.lo), posed_(s.hi), s.t);
    posed_.add(at);
    if (!side_by_side) {
      placement_.place(editor_, s.v, at);
    } else {
      ids.push_back(s.v);
      targets.push_back(at);
    }
    dist_.push_back(0.0f);
    sign_.push_back(0);
  }
  if (side_by_side) placement_.place_all(editor_, ids.data(), targets.data(), n);
  intersections_ += n;
  for (const auto& [a, b] : merge_candidates_) merges_.merge_if_near(mesh_, a, b);
}

// The corner split_face makes on the side (ka, kb) of face `t` at its crossing `s`.
Cutter::Corner Cutter::split_corner(const Triangle& t, int ka, int kb, const Split& s) const {
  const VertexId v = merges_.merged(s.v);
  float bary[3] = {0.0f, 0.0f, 0.0f};  // by index: glm's operator[] branches on it
  const float wa = t[ka] == s.lo ? 1.0f - s.t : s.t;
  bary[ka] = wa;
  bary[kb] = 1.0f - wa;
  return {v, glm::vec3(bary[0], bary[1], bary[2])};
}

// Finds the crossings of a face the plane crosses, in the order split_face uses them. A face whose
// lone corner has two long edges to corners a hair apart (a needle: the lips of a narrow tear, a
// sliver) has its two crossings rounded to one bind position or a few float steps apart: they
// become one vertex, and the needle's tip beyond the plane (a zero-area triangle) is not made.
void Cutter::split_crossings(FaceId f) {
  const Triangle& t = mesh_.face(f);
  const std::int8_t s[3] = {sign_[t[0].index], sign_[t[1].index], sign_[t[2].index]};
  const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0, neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
  // Two entries a face, each pushed alone (a range insert costs more than the pair).
  if (!pos || !neg) {
    face_crossings_.push_back(nullptr);
    face_crossings_.push_back(nullptr);
    return;
  }
  for (int k = 0; k < 3; ++k)
    if (s[k] == 0) {
      face_crossings_.push_back(&split_edge(t[(k + 1) % 3], t[(k + 2) % 3]));
      face_crossings_.push_back(nullptr);
      return;
    }
  int lone = 0;
  for (int k = 0; k < 3; ++k)
    if (s[k] != s[(k + 1) % 3] && s[k] != s[(k + 2) % 3]) lone = k;
  const Split& a = split_edge(t[lone], t[(lone + 1) % 3]);
  const Split& b = split_edge(t[lone], t[(lone + 2) % 3]);
  face_crossings_.push_back(&a);
  face_crossings_.push_back(&b);
  merge_candidates_.emplace_back(a.v, b.v);
}

// Plans the removal of a face the plane crosses and the up to three faces replacing it
// (`crossings`: its two in face_crossings_), in planned_ and crossed_.
void Cutter::split_face(FaceId f, const Split* const* crossings) {
  const Triangle t = mesh_.face(f);
  const std::int8_t s[3] = {sign_[t[0].index], sign_[t[1].index], sign_[t[2].index]};
  const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0, neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
  if (!pos || !neg) return;
  static const glm::vec3 kOwn[3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  auto corner = [&](int k) { return Corner{t[k], kOwn[k]}; };  // the parent's corner k itself
  auto emit = [&](const Corner& a, const Corner& b, const Corner& c) {
    if (a.v == b.v || b.v == c.v || a.v == c.v) return;  // the tip of a needle whose crossings merged
    planned_.push_back({{a.v, b.v, c.v}, f, {a.bary, b.bary, c.bary}});
  };
  crossed_.emplace_back(f, static_cast<std::uint32_t>(planned_.size()));
  int zero = -1;
  for (int k = 0; k < 3; ++k)
    if (s[k] == 0) zero = k;
  if (zero >= 0) {  // the plane runs through one corner and the opposite edge
    const int k1 = (zero + 1) % 3, k2 = (zero + 2) % 3;
    const Corner m = split_corner(t, k1, k2, *crossings[0]);
    emit(corner(zero), corner(k1), m);
    emit(corner(zero), m, corner(k2));
    return;
  }
  int lone = 0;  // the corner alone on its side
  for (int k = 0; k < 3; ++k)
    if (s[k] != s[(k + 1) % 3] && s[k] != s[(k + 2) % 3]) lone = k;
  const int k1 = (lone + 1) % 3, k2 = (lone + 2) % 3;
  const Corner m1 = split_corner(t, lone, k1, *crossings[0]), m2 = split_corner(t, lone, k2, *crossings[1]);
  emit(corner(lone), m1, m2);
  // The quad (m1, k1, k2, m2): split along its shorter diagonal.
  const float d1 = glm::length(posed_(m1.v) - posed_(t[k2]));
  const float d2 = glm::length(posed_(t[k1]) - posed_(m2.v));
  if (d1 <= d2) {
    emit(m1, corner(k1), corner(k2));
    emit(m1, corner(k2), m2);
  } else {
    emit(m1, corner(k1), m2);
    emit(corner(k1), corner(k2), m2);
  }
}

// Makes the planned faces, each crossed face removed before its own, in one editor batch; with
// `moved`, only the planned faces it does not flag (move_positive_rim makes those).
void Cutter::make_planned(const std::vector<std::uint8_t>* moved) {
  const auto first_new_face = static_cast<std::uint32_t>(mesh_.face_slots());
  FaceBatch batch;
  batch.reserve(planned_.size(), crossed_.size());
  for (std::size_t c = 0; c < crossed_.size(); ++c) {
    batch.remove(crossed_[c].first);
    const std::size_t end = c + 1 < crossed_.size() ? crossed_[c + 1].second : planned_.size();
    for (std::size_t i = crossed_[c].second; i < end; ++i)
      if (!moved || !(*moved)[i]) batch.add_from(planned_[i].t, planned_[i].parent, planned_[i].bary);
  }
  editor_.apply(batch);
  detail::append_run(rim_candidates_, first_new_face, static_cast<std::uint32_t>(mesh_.face_slots()));
}

}  // namespace deepcut::detail
