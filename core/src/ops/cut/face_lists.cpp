// SPDX-License-Identifier: MIT
#include "ops/cut/face_lists.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <iterator>

#include "deepcut/core/parallel.h"

namespace deepcut::detail {
namespace {

// Consecutive face ids as a random-access iterator: vector::insert, its one use, then sizes the
// insertion once and writes each id in place, with no fill first (an input iterator would be
// inserted one push at a time, a resize would fill first). A proxy iterator, as C++20's
// iota_view iterator: `reference` is the id itself, not a reference to a stored one, which is
// all insert reads (*it, ++, it - it); the other random-access operations are complete.
class IdCounter {
 public:
  using iterator_category = std::random_access_iterator_tag;
  using value_type = FaceId;
  using difference_type = std::ptrdiff_t;
  using pointer = const FaceId*;
  using reference = FaceId;
  explicit IdCounter(std::uint32_t i) : i_(i) {}
  FaceId operator*() const { return FaceId(i_); }
  FaceId operator[](difference_type n) const { return *(*this + n); }
  IdCounter& operator++() { return *this += 1; }
  IdCounter operator++(int) { return IdCounter(i_++); }
  IdCounter& operator--() { return *this -= 1; }
  IdCounter operator--(int) { return IdCounter(i_--); }
  IdCounter& operator+=(difference_type n) {
    i_ += static_cast<std::uint32_t>(n);
    return *this;
  }
  IdCounter& operator-=(difference_type n) { return *this += -n; }
  IdCounter operator+(difference_type n) const { return IdCounter(*this) += n; }
  friend IdCounter operator+(difference_type n, const IdCounter& it) { return it + n; }
  IdCounter operator-(difference_type n) const { return IdCounter(*this) -= n; }
  difference_type operator-(const IdCounter& o) const {
    return static_cast<difference_type>(i_) - static_cast<difference_type>(o.i_);
  }
  bool operator==(const IdCounter& o) const { return i_ == o.i_; }
  bool operator!=(const IdCounter& o) const { return i_ != o.i_; }
  bool operator<(const IdCounter& o) const { return i_ < o.i_; }
  bool operator>(const IdCounter& o) const { return o < *this; }
  bool operator<=(const IdCounter& o) const { return !(o < *this); }
  bool operator>=(const IdCounter& o) const { return !(*this < o); }

 private:
  std::uint32_t i_;
};

inline void flag_corners(std::uint8_t* used, VertexId a, VertexId b, VertexId c) {
  set_flag(used, a.index);
  set_flag(used, b.index);
  set_flag(used, c.index);
}

// The first face from `i` on (below `end`) whose corner bits are not `c` (or, with
// kCheckDeleted, that is deleted): the end of a run of faces on one side. With kFlag, the
// corners of the faces it reads are flagged in `used`. Without deleted faces, four faces a step
// with one test for the four.
template <bool kCheckDeleted, bool kFlag>
std::uint32_t run_end(const SurfaceMesh& mesh, const std::uint8_t* bits, std::uint8_t* used, std::uint32_t i,
                      std::uint32_t end, unsigned c) {
  const Triangle* faces = mesh.faces().data();
  if constexpr (!kCheckDeleted) {
    auto other = [&](const Triangle& t) {  // nonzero when face t is not of the run
      if constexpr (kFlag) flag_corners(used, t[0], t[1], t[2]);
      return corner_bits(t, bits) ^ c;
    };
    const Triangle* at = faces + i;
    const Triangle* const stop = faces + (end - i) / 4 * 4 + i;
    for (; at != stop; at += 4) {
      const Triangle t0 = at[0], t1 = at[1], t2 = at[2], t3 = at[3];
      if ((other(t0) | other(t1) | other(t2) | other(t3)) != 0) break;
    }
    i = static_cast<std::uint32_t>(at - faces);
  }
  for (; i < end; ++i) {
    const Triangle t = faces[i];
    if constexpr (kFlag) flag_corners(used, t[0], t[1], t[2]);
    if (corner_bits(t, bits) != c) break;
    if (kCheckDeleted && mesh.is_deleted(FaceId(i))) break;
  }
  return i;
}

// The faces [b, e) into `out`, as scan_faces files them.
template <bool kCheckDeleted, bool kFlag>
void scan_chunk(const SurfaceMesh& mesh, const std::uint8_t* bits, std::uint8_t* used, std::uint32_t b,
                std::uint32_t e, ScannedFaces& out) {
  const Triangle* faces = mesh.faces().data();
  for (std::uint32_t i = b; i < e;) {
    const Triangle t = faces[i];
    if constexpr (kFlag) flag_corners(used, t[0], t[1], t[2]);
    if (kCheckDeleted && mesh.is_deleted(FaceId(i))) {
      ++i;
      continue;
    }
    const unsigned c = corner_bits(t, bits);
    if (c > 2) {
      ((c & 3) == 3 ? out.crossed : out.touching).push_back(FaceId(i));
      ++i;
      continue;
    }
    const std::uint32_t end = run_end<kCheckDeleted, kFlag>(mesh, bits, used, i + 1, e, c);
    append_run(out.clean[c - 1], i, end);
    i = end;
  }
}

}  // namespace

void append_run(std::vector<FaceId>& list, std::uint32_t i, std::uint32_t end) {
  list.insert(list.end(), IdCounter(i), IdCounter(end));
}

void follow_moved_faces(const std::vector<std::pair<FaceId, FaceId>>& moved, FaceId first_new,
                        std::vector<FaceId>& piece) {
  const bool below = std::is_sorted(piece.begin(), piece.end()) && (piece.empty() || piece.back() < first_new);
  if (!below) {
    for (FaceId& f : piece) {
      const auto it = std::lower_bound(moved.begin(), moved.end(), std::make_pair(f, FaceId()),
                                       [](const auto& x, const auto& y) { return x.first < y.first; });
      if (it != moved.end() && it->first == f) f = it->second;
    }
    std::sort(piece.begin(), piece.end());
    return;
  }
  std::vector<FaceId> added;
  for (const auto& [f, g] : moved) {
    const auto it = std::lower_bound(piece.begin(), piece.end(), f);
    if (it == piece.end() || *it != f) continue;
    added.push_back(g);
    *it = FaceId();  // invalid: dropped below
  }
  if (added.empty()) return;
  piece.erase(std::remove(piece.begin(), piece.end(), FaceId()), piece.end());
  std::sort(added.begin(), added.end());
  piece.insert(piece.end(), added.begin(), added.end());
}

void merge_sorted(std::vector<FaceId>& list, const std::vector<FaceId>& more) {
  const auto mid = static_cast<std::ptrdiff_t>(list.size());
  list.insert(list.end(), more.begin(), more.end());
  if (mid > 0 && !more.empty() && more.front() < list[static_cast<std::size_t>(mid - 1)])
    std::inplace_merge(list.begin(), list.begin() + mid, list.end());
}

std::vector<ScannedFaces> scan_faces(const SurfaceMesh& mesh, const std::uint8_t* bits, std::uint8_t* used) {
  const std::size_t nf = mesh.face_slots();
  const std::size_t grain = grain_per_thread(nf, kMinPassGrain);
  std::vector<ScannedFaces> found((nf + grain - 1) / grain);
  // Each chunk's side lists reserved here, on the calling thread, for every face of the chunk:
  // all of them then come from the caller's heap (arena), whichever thread fills them, instead
  // of growing the heap of a pool thread into fresh pages.
  for (std::size_t c = 0; c < found.size(); ++c) {
    const std::size_t size = std::min(nf, (c + 1) * grain) - c * grain;
    for (std::vector<FaceId>& list : found[c].clean) list.reserve(size);
  }
  // Without deleted faces (a mesh as loaded or compacted) the loops need not look for them.
  const bool any_deleted = mesh.face_count() != nf;
  parallel_for(nf, grain, [&](std::size_t b, std::size_t e) {
    ScannedFaces& out = found[b / grain];
    const auto lo = static_cast<std::uint32_t>(b), hi = static_cast<std::uint32_t>(e);
    out.end = hi;
    if (any_deleted && used)
      scan_chunk<true, true>(mesh, bits, used, lo, hi, out);
    else if (any_deleted)
      scan_chunk<true, false>(mesh, bits, used, lo, hi, out);
    else if (used)
      scan_chunk<false, true>(mesh, bits, used, lo, hi, out);
    else
      scan_chunk<false, false>(mesh, bits, used, lo, hi, out);
  });
  return found;
}

bool all_flagged(const std::uint8_t* flags, std::size_t count) {
  // Read as bytes once the threads that set them are joined: memchr, as a loop of flag_of
  // (atomic loads) is not vectorised (about 25 times slower over 600k flags). In parts over the
  // pool (a flag a vertex: 2M at 4M triangles).
  return parallel_reduce(
             count, grain_per_thread(count, 8 * kMinPassGrain), 1,
             [&](std::size_t b, std::size_t e) {
               return std::memchr(flags + b, 0, e - b) == nullptr ? 1 : 0;
             },
             [](int a, int b) { return a & b; }) != 0;
}

void clear_flags(std::uint8_t* flags, std::size_t count) {
  parallel_for(count, grain_per_thread(count, 8 * kMinPassGrain),
               [&](std::size_t b, std::size_t e) { std::memset(flags + b, 0, e - b); });
}

}  // namespace deepcut::detail
