// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "deepcut/core/operation_room.h"
#include "deepcut/core/smallest_fit.h"

namespace {

using deepcut::take_smallest_fit;

std::size_t room_of(const std::vector<int>& v) { return v.capacity(); }

std::vector<int> with_room(std::size_t n) {
  std::vector<int> v;
  v.reserve(n);
  return v;
}

// The smallest spare that holds what is needed and at most twice it is taken; the first of equal
// rooms; none when every spare is too small or far too large.
TEST(SmallestFit, TakesTheSmallestThatHoldsAtMostTwiceTheNeed) {
  std::vector<std::vector<int>> spare;
  for (int n : {50, 400, 120, 201, 120}) spare.push_back(with_room(static_cast<std::size_t>(n)));
  const int* second_120 = spare[4].data();
  const int* first_120 = spare[2].data();
  EXPECT_EQ(take_smallest_fit(spare, 100, room_of).data(), first_120);
  EXPECT_EQ(take_smallest_fit(spare, 100, room_of).data(), second_120);
  EXPECT_EQ(take_smallest_fit(spare, 100, room_of).capacity(), 201u);  // 2 x 100 + 1 still fits
  EXPECT_EQ(take_smallest_fit(spare, 100, room_of).capacity(), 0u);    // 400 is far larger, 50 too small
  EXPECT_EQ(spare.size(), 2u);
}

// A buffer made with fixed room past its size (the posed normals' operation_corner_room) is far
// more than twice the need of a small piece of its own size: with the room's bound it is reused.
TEST(SmallestFit, AnUpperBoundTakesABufferMadeWithRoomForAPieceItsOwnSize) {
  const std::size_t faces = 300, need = 3 * faces;
  const std::size_t made = deepcut::operation_corner_room(faces);
  ASSERT_GT(made, 2 * need + 1) << "the fixed room makes a small piece's buffer more than twice its need";
  std::vector<std::vector<int>> spare;
  spare.push_back(with_room(made));
  EXPECT_EQ(take_smallest_fit(spare, need, room_of).capacity(), 0u);
  const std::vector<int> taken = take_smallest_fit(spare, need, 2 * made, room_of);
  EXPECT_GE(taken.capacity(), made);
  EXPECT_TRUE(spare.empty());
}

}  // namespace
