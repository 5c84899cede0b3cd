// SPDX-License-Identifier: MIT
#include "deepcut/core/attributes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/ext/vector_float1.hpp>
#include <string>
#include <vector>

#include "deepcut/core/parallel.h"

namespace deepcut {

TEST(AttributesTest, arrays_grow_together_and_blend_by_type) {
  AttributeSet set;
  auto& f = set.add<glm::vec2>("c:uv0", glm::vec2(-1.0f));
  auto& j = set.add<glm::u16vec4>("v:joints0");
  set.resize(2);
  EXPECT_EQ(f.size(), 2u);
  EXPECT_EQ(f[1], glm::vec2(-1.0f));  // default value
  f[0] = {0.0f, 0.0f};
  f[1] = {2.0f, 4.0f};
  j[0] = {1, 2, 3, 4};
  j[1] = {5, 6, 7, 8};
  const std::uint32_t src[2] = {0, 1};
  const float w[2] = {0.25f, 0.75f};
  set.push_blend(src, w, 2);
  ASSERT_EQ(set.size(), 3u);
  EXPECT_FLOAT_EQ(f[2].x, 1.5f);
  EXPECT_FLOAT_EQ(f[2].y, 3.0f);
  EXPECT_EQ(j[2], glm::u16vec4(5, 6, 7, 8));  // integers take the dominant source
}

TEST(AttributesTest, push_default_appends_defaults_after_the_values_kept) {
  AttributeSet set;
  auto& f = set.add<glm::vec3>("c:normal", glm::vec3(0.0f, 0.0f, 1.0f));
  auto& g = set.add<std::uint8_t>("f:flag", std::uint8_t(7));
  set.resize(2);
  f[0] = glm::vec3(1.0f);
  g[1] = 3;
  set.push_default(5);
  set.push_default(0);
  ASSERT_EQ(set.size(), 7u);
  EXPECT_EQ(f[0], glm::vec3(1.0f));
  EXPECT_EQ(g[1], 3);
  for (std::size_t i = 1; i < 7; ++i) EXPECT_EQ(f[i], glm::vec3(0.0f, 0.0f, 1.0f)) << i;
  for (std::size_t i = 2; i < 7; ++i) EXPECT_EQ(g[i], 7) << i;
}

TEST(AttributesTest, add_rejects_duplicates_and_get_rejects_missing_or_wrong_type) {
  AttributeSet set;
  set.add<float>("v:x");
  EXPECT_THROW(set.add<float>("v:x"), Error);
  EXPECT_THROW(set.get<float>("v:y"), Error);
  EXPECT_THROW(set.get<glm::vec3>("v:x"), Error);
  EXPECT_EQ(set.find<float>("v:y"), nullptr);
}

TEST(AttributesTest, copy_is_deep_and_gather_reorders) {
  AttributeSet set;
  auto& a = set.add<float>("v:a");
  set.resize(3);
  a[0] = 10;
  a[1] = 11;
  a[2] = 12;
  AttributeSet copy = set;
  copy.get<float>("v:a")[0] = 99;
  EXPECT_EQ(a[0], 10);
  set.gather({2, 0});
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.get<float>("v:a")[0], 12);
  EXPECT_EQ(set.get<float>("v:a")[1], 10);
  EXPECT_TRUE(copy.elements_equal(1, 1));
  EXPECT_FALSE(copy.elements_equal(0, 1));
}

TEST(AttributesTest, set_blend3_equals_three_set_blends) {
  // The editor's one-call corner blend must give exactly what blending corner by corner gives.
  AttributeSet one, three;
  for (AttributeSet* set : {&one, &three}) {
    auto& uv = set->add<glm::vec2>("c:uv0");
    auto& j = set->add<glm::u16vec4>("c:ids");
    set->resize(6);
    for (std::uint32_t i = 0; i < 3; ++i) {
      uv[i] = {0.1f * float(i) + 0.37f, 1.0f / float(i + 3)};
      j[i] = glm::u16vec4(std::uint16_t(i + 1));
    }
  }
  const float w[9] = {0.2f, 0.3f, 0.5f, 1.0f, 0.0f, 0.0f, 0.1f, 0.7f, 0.2f};
  one.set_blend3(3, 0, w);
  const std::uint32_t src[3] = {0, 1, 2};
  for (int k = 0; k < 3; ++k) three.set_blend(3 + std::size_t(k), src, w + 3 * k, 3);
  for (std::size_t i = 3; i < 6; ++i) {
    EXPECT_EQ(one.get<glm::vec2>("c:uv0")[i], three.get<glm::vec2>("c:uv0")[i]) << i;
    EXPECT_EQ(one.get<glm::u16vec4>("c:ids")[i], three.get<glm::u16vec4>("c:ids")[i]) << i;
  }
  EXPECT_EQ(one.get<glm::u16vec4>("c:ids")[5], glm::u16vec4(2));  // the dominant source
}

TEST(AttributesTest, gather_groups_appends_the_listed_groups_run_by_run) {
  // Runs, lone groups and a jump back, in groups of 1 and 3; the room reserved is what the hook
  // is handed; another type is refused.
  AttributeArray<float> from;
  for (int i = 0; i < 30; ++i) from.data().push_back(float(i));
  const std::vector<std::uint32_t> keep = {2, 3, 4, 7, 9, 0, 1};
  for (std::size_t group : {1u, 3u}) {
    AttributeArray<float> to;
    static std::size_t reserved = 0;
    reserved = 0;
    from.gather_groups(to, keep, group, [](void*, std::size_t bytes) { reserved = bytes; });
    EXPECT_EQ(reserved, keep.size() * group * sizeof(float));
    ASSERT_EQ(to.size(), keep.size() * group);
    for (std::size_t i = 0; i < keep.size(); ++i)
      for (std::size_t g = 0; g < group; ++g) EXPECT_EQ(to[i * group + g], from[keep[i] * group + g]) << i;
  }
  const auto subset = from.clone_subset(keep);
  ASSERT_EQ(subset->size(), keep.size());
  EXPECT_EQ(*static_cast<const float*>(subset->element_data(3)), 7.0f);
  AttributeArray<int> other;
  EXPECT_THROW(from.gather_groups(other, keep, 1, nullptr), Error);
}

namespace {

// The arrays both batch tests fill, alike in `batch` and `single`: three float types and an
// integer one (the first test adds two more).
struct BatchArrays {
  AttributeArray<glm::vec3>& v;
  AttributeArray<glm::u16vec4>& j;
  AttributeArray<float>& f;
  AttributeArray<glm::vec2>& v2;
};

BatchArrays add_batch_arrays(AttributeSet& set) {
  return {set.add<glm::vec3>("c:v"), set.add<glm::u16vec4>("c:ids"), set.add<float>("c:f"),
          set.add<glm::vec2>("c:v2")};
}

// Every array of `batch` holds the same bytes as `single`'s, element by element.
void expect_same_elements(const AttributeSet& batch, const AttributeSet& single) {
  for (const std::string& name : batch.names()) {
    const AttributeArrayBase& a = *batch.base(name);
    const AttributeArrayBase& b = *single.base(name);
    ASSERT_EQ(a.size(), batch.size()) << name;
    for (std::size_t i = 0; i < a.size(); ++i)
      ASSERT_EQ(std::memcmp(a.element_data(i), b.element_data(i), a.element_bytes()), 0) << name << " " << i;
  }
}

}  // namespace

TEST(AttributesTest, batches_equal_the_single_calls_in_turn) {
  // One call per array for many new elements must leave exactly what the calls one element at a
  // time leave: the same blends (negative zero and NaN included), the same integer choices.
  AttributeSet batch, single;
  for (AttributeSet* set : {&batch, &single}) {
    auto [v, j, f, v2] = add_batch_arrays(*set);
    auto& v4 = set->add<glm::vec4>("c:v4");
    auto& c = set->add<glm::u8vec4>("c:colour");
    set->resize(9);
    for (std::uint32_t i = 0; i < 9; ++i) {
      v[i] = {0.1f * float(i) - 0.35f, -0.0f, i == 4 ? std::nanf("") : 1.0f / float(i + 3)};
      j[i] = glm::u16vec4(std::uint16_t(i + 1));
      f[i] = i % 2 ? -0.0f : 2.5f * float(i);
      v2[i] = {i % 3 ? -0.0f : 0.7f * float(i), 1e-41f * float(i)};
      v4[i] = {std::sin(float(i)), i == 5 ? INFINITY : -0.0f, 0.25f * float(i), -1.0f / float(i + 1)};
      c[i] = glm::u8vec4(std::uint8_t(3 * i), 0, std::uint8_t(255 - i), 1);
    }
  }
  const std::uint32_t triples[3] = {2, 0, 1};
  const float w[27] = {0.2f, 0.3f, 0.5f, 1.0f, 0.0f, 0.0f, 0.1f, 0.7f, 0.2f, 0.0f, 0.0f, 1.0f, 0.5f, 0.5f, 0.0f,
                       0.3f, 0.3f, 0.4f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f};
  batch.push_blend3_batch(triples, w, 3);
  for (int i = 0; i < 3; ++i) single.push_blend3(3 * std::size_t(triples[i]), w + 9 * i);
  const std::uint32_t src[6] = {1, 4, 7, 7, 0, 3};
  batch.push_blend_batch(src, w, 2, 3);
  for (int i = 0; i < 3; ++i) single.push_blend(src + 2 * i, w + 2 * i, 2);
  batch.push_blend_batch(src, w + 3, 1, 6);
  for (int i = 0; i < 6; ++i) single.push_blend(src + i, w + 3 + i, 1);
  batch.push_copy_batch(src, 6);
  for (std::uint32_t s : src) single.push_copy(s);
  // Sources made earlier in the same batch (elements 33 and 34 are its first two), three sources.
  const std::uint32_t later[8] = {2, 30, 33, 5, 33, 34, 1, 0};
  batch.push_blend_batch(later, w + 7, 2, 4);
  for (int i = 0; i < 4; ++i) single.push_blend(later + 2 * i, w + 7 + 2 * i, 2);
  batch.push_blend_batch(later, w + 11, 3, 2);
  for (int i = 0; i < 2; ++i) single.push_blend(later + 3 * i, w + 11 + 3 * i, 3);
  ASSERT_EQ(batch.size(), 9u + 9u + 3u + 6u + 6u + 4u + 2u);
  ASSERT_EQ(single.size(), batch.size());
  expect_same_elements(batch, single);
}

TEST(AttributesTest, large_batches_run_side_by_side_equal_the_single_calls_in_turn) {
  // 2048+ new elements an array: each array of the set appends its batch as a pool task of its
  // own, sources made earlier in the same batch included; the result is what the single calls
  // leave, element by element.
  constexpr std::uint32_t kOld = 300, kBlends = 2600, kCopies = 2300, kFaces = 900;
  AttributeSet batch, single;
  for (AttributeSet* set : {&batch, &single}) {
    auto [v, j, f, v2] = add_batch_arrays(*set);
    set->resize(kOld);
    for (std::uint32_t i = 0; i < kOld; ++i) {
      v[i] = {0.01f * float(i) - 0.35f, std::sin(float(i)), 1.0f / float(i + 3)};
      j[i] = glm::u16vec4(std::uint16_t(i + 1), std::uint16_t(2 * i), 0, 7);
      f[i] = i % 2 ? -0.0f : 2.5f * float(i);
      v2[i] = {std::cos(float(i)), 1e-41f * float(i)};
    }
  }
  std::vector<std::uint32_t> src(3 * kBlends), copies(kCopies), triples(kFaces);
  std::vector<float> w(9 * std::size_t(kFaces) + 3 * kBlends);
  for (std::uint32_t i = 0; i < kBlends; ++i)
    for (std::uint32_t k = 0; k < 3; ++k)  // every third source an element the batch made
      src[3 * i + k] = (i + k) % 3 == 0 && i > 0 ? kOld + (7 * i + k) % i : (11 * i + 5 * k) % kOld;
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = i % 7 == 0 ? 0.0f : std::cos(float(i)) * 0.6f;
  const std::size_t saved = thread_count();
  set_thread_count(3);
  batch.push_blend_batch(src.data(), w.data(), 2, kBlends);
  batch.push_blend_batch(src.data(), w.data(), 3, kBlends / 2);
  std::size_t size = batch.size();
  for (std::uint32_t i = 0; i < kCopies; ++i) copies[i] = (13 * i) % std::uint32_t(size);
  batch.push_copy_batch(copies.data(), kCopies);
  size = batch.size();
  for (std::uint32_t i = 0; i < kFaces; ++i) triples[i] = (17 * i) % std::uint32_t(size / 3);
  batch.push_blend3_batch(triples.data(), w.data(), kFaces);
  set_thread_count(saved);
  for (std::uint32_t i = 0; i < kBlends; ++i) single.push_blend(&src[2 * i], &w[2 * i], 2);
  for (std::uint32_t i = 0; i < kBlends / 2; ++i) single.push_blend(&src[3 * i], &w[3 * i], 3);
  for (std::uint32_t s : copies) single.push_copy(s);
  for (std::uint32_t i = 0; i < kFaces; ++i) single.push_blend3(3 * std::size_t(triples[i]), &w[9 * i]);
  ASSERT_EQ(batch.size(), kOld + kBlends + kBlends / 2 + kCopies + 3 * kFaces);
  ASSERT_EQ(single.size(), batch.size());
  expect_same_elements(batch, single);
}

// Each component of corner k: ((0 + s0 w0) + s1 w1) + s2 w2, one float operation at a time.
template <class T>
T scalar_blend(const T* s, const float* w) {
  T out(0.0f);
  for (int c = 0; c < T::length(); ++c) {
    float x = 0.0f;
    for (int i = 0; i < 3; ++i) {
      const volatile float term = s[i][c] * w[i];  // rounded alone, as the rule rounds it
      x = x + term;
    }
    out[c] = x;
  }
  return out;
}

template <class T>
void expect_batches_blend_exactly() {
  // Runs of faces longer than a batch's stack run, parents up to the array's last face (read
  // right at its end), zeros of both signs and subnormals among the values.
  constexpr std::uint32_t kFaces = 40, kNew = 75;
  AttributeArray<T> array;
  std::vector<T>& data = array.data();
  for (std::uint32_t i = 0; i < 3 * kFaces; ++i) {
    T x(0.0f);
    for (int c = 0; c < T::length(); ++c)
      x[c] = (i + c) % 7 == 0 ? -0.0f : (i + c) % 11 == 0 ? 1e-41f : std::sin(float(3 * i + c)) * 40.0f;
    data.push_back(x);
  }
  data.shrink_to_fit();  // no room past the end: the batch grows the array itself
  std::vector<std::uint32_t> parents(kNew);
  std::vector<float> w(9 * kNew);
  for (std::uint32_t i = 0; i < kNew; ++i) parents[i] = i % 3 == 0 ? kFaces - 1 : (7 * i) % kFaces;
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = i % 5 == 0 ? 0.0f : std::cos(float(i)) * 0.75f;
  const std::vector<T> before = data;
  array.push_blend3_batch(parents.data(), w.data(), kNew);
  ASSERT_EQ(data.size(), 3 * std::size_t(kFaces + kNew));
  for (std::uint32_t i = 0; i < kNew; ++i)
    for (int k = 0; k < 3; ++k) {
      const T expected = scalar_blend(&before[3 * parents[i]], &w[9 * i + 3 * k]);
      EXPECT_EQ(std::memcmp(&expected, &data[3 * (kFaces + i) + k], sizeof(T)), 0) << T::length() << " face " << i;
    }
  EXPECT_EQ(std::memcmp(before.data(), data.data(), before.size() * sizeof(T)), 0);  // the sources untouched
}

TEST(AttributesTest, batches_blend_every_float_width_exactly_as_the_scalar_rule) {
  expect_batches_blend_exactly<glm::vec1>();
  expect_batches_blend_exactly<glm::vec2>();
  expect_batches_blend_exactly<glm::vec3>();
  expect_batches_blend_exactly<glm::vec4>();
}

}  // namespace deepcut
