// SPDX-License-Identifier: MIT
// UninitVector leaves only value-initialised elements unwritten: what it held, explicit values and
// copies are as in a std::vector.
#include "deepcut/core/uninit_vector.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <iterator>
#include <type_traits>

namespace deepcut {
namespace {

static_assert(std::is_same<UninitVector<float>::allocator_type, UninitAllocator<float>>::value);

static_assert(std::is_same<UnfilledVector<float>::allocator_type, UninitAllocator<float, false>>::value);

struct WithDefaults {
  std::uint32_t a = 7, b = 9;
};

// Growing an UninitVector default-initialises: a type's default member values are written.
// Growing an UnfilledVector writes nothing: the storage keeps what it held (here, after clear(),
// the values written before, since the memory is kept).
TEST(UninitVector, UnfilledGrowthWritesNoDefaults) {
  UninitVector<WithDefaults> with(64, WithDefaults{1, 2});
  with.clear();
  with.resize(64);
  for (const WithDefaults& w : with) ASSERT_EQ(w.a * 100 + w.b, 709u);
  UnfilledVector<WithDefaults> unfilled(64, WithDefaults{1, 2});
  const WithDefaults* storage = unfilled.data();
  unfilled.clear();
  unfilled.resize(64);
  ASSERT_EQ(unfilled.data(), storage);
  for (const WithDefaults& w : unfilled) ASSERT_EQ(w.a * 100 + w.b, 102u);
  unfilled.resize(128, WithDefaults{});  // explicit values are written
  for (std::size_t i = 64; i < 128; ++i) ASSERT_EQ(unfilled[i].a * 100 + unfilled[i].b, 709u) << i;
}

// Growing it keeps the elements it held (and their order); shrinking keeps the first ones.
TEST(UninitVector, ResizeKeepsTheElementsItHeld) {
  UninitVector<std::uint32_t> v;
  for (std::uint32_t i = 0; i < 100; ++i) v.push_back(3 * i + 1);
  v.resize(100000);  // moves to a larger allocation
  ASSERT_EQ(v.size(), 100000u);
  for (std::uint32_t i = 0; i < 100; ++i) EXPECT_EQ(v[i], 3 * i + 1) << i;
  v.resize(10);
  ASSERT_EQ(v.size(), 10u);
  for (std::uint32_t i = 0; i < 10; ++i) EXPECT_EQ(v[i], 3 * i + 1) << i;
}

// An explicit value is constructed in every new element, by resize, the sized constructor and
// assign, over memory that held other values.
TEST(UninitVector, ExplicitValuesAreConstructed) {
  const glm::mat3 seven(glm::vec3(7.0f), glm::vec3(7.0f), glm::vec3(7.0f));
  UninitVector<glm::mat3> v(1000, seven);
  for (const glm::mat3& m : v) ASSERT_EQ(m, seven);
  v.clear();  // keeps the memory: the 7s are still there
  v.resize(1000, glm::mat3(2.0f));
  for (const glm::mat3& m : v) ASSERT_EQ(m, glm::mat3(2.0f));
  v.clear();
  v.assign(1000, glm::mat3(0.0f));
  for (const glm::mat3& m : v) ASSERT_EQ(m, glm::mat3(0.0f));
  v.resize(1500, seven);
  for (std::size_t i = 0; i < 1000; ++i) ASSERT_EQ(v[i], glm::mat3(0.0f)) << i;
  for (std::size_t i = 1000; i < 1500; ++i) ASSERT_EQ(v[i], seven) << i;
  const float values[] = {1.5f, -2.0f, 0.25f};
  UninitVector<float> f;
  f.assign(std::begin(values), std::end(values));
  EXPECT_EQ(f, (UninitVector<float>{1.5f, -2.0f, 0.25f}));
}

// A copy (constructed or assigned) compares equal, element for element, and is its own array.
TEST(UninitVector, CopiesCompareEqual) {
  UninitVector<glm::vec3> v(5000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = glm::vec3(float(i), -float(i), 0.5f * float(i));
  const UninitVector<glm::vec3> copy(v);
  EXPECT_EQ(copy, v);
  EXPECT_NE(copy.data(), v.data());
  UninitVector<glm::vec3> assigned(3, glm::vec3(9.0f));
  assigned = v;
  EXPECT_EQ(assigned, v);
  assigned[4999].x += 1.0f;
  EXPECT_NE(assigned, v);
}

}  // namespace
}  // namespace deepcut
