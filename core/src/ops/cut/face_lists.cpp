// SPDX-License-Identifier: MIT
#include "ops/cut/face_lists.h"

#include <algorithm>
#include <cstddef>
#include <iterator>

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

}  // namespace deepcut::detail
