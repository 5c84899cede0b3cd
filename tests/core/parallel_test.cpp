// SPDX-License-Identifier: MIT
#include "deepcut/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "first_of_class.h"
#include "thread_count.h"

namespace deepcut {
namespace {

using ThreadCountGuard = test::ThreadCount;  // restores the pool size a test changed

// A float sum whose value depends on the order of the additions.
float chunked_sum(const std::vector<float>& v, std::size_t grain) {
  return parallel_reduce(
      v.size(), grain, 0.0f,
      [&](std::size_t b, std::size_t e) {
        float s = 0.0f;
        for (std::size_t i = b; i < e; ++i) s += v[i];
        return s;
      },
      [](float a, float b) { return a + b; });
}

TEST(Parallel, ForCoversEveryIndexOnce) {
  for (std::size_t threads : {1u, 2u, 3u}) {
    ThreadCountGuard guard(threads);
    for (std::size_t n : {0u, 1u, 7u, 1000u, 100003u}) {
      std::vector<int> hits(n, 0);
      parallel_for(n, 97, [&](std::size_t b, std::size_t e) {
        EXPECT_LT(b, e);
        EXPECT_LE(e - b, 97u);
        for (std::size_t i = b; i < e; ++i) ++hits[i];
      });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i], 1) << "n " << n << " i " << i << " threads " << threads;
    }
  }
}

TEST(Parallel, ChunkBoundariesDependOnlyOnGrain) {
  std::vector<std::vector<std::size_t>> starts;
  for (std::size_t threads : {1u, 2u, 4u}) {
    ThreadCountGuard guard(threads);
    std::vector<std::size_t> s(11, 0);
    parallel_for(1000, 100, [&](std::size_t b, std::size_t e) { s[b / 100] = e; });
    starts.push_back(s);
  }
  EXPECT_EQ(starts[0], starts[1]);
  EXPECT_EQ(starts[0], starts[2]);
  EXPECT_EQ(starts[0][9], 1000u);
}

TEST(Parallel, ReduceIsBitIdenticalForAnyThreadCount) {
  std::vector<float> v(200001);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(float(i)) * 1e3f + 1e-3f * float(i % 7);
  float serial = 0.0f;
  {
    ThreadCountGuard guard(1);
    serial = chunked_sum(v, 4096);
  }
  for (std::size_t threads : {2u, 3u, 8u}) {
    ThreadCountGuard guard(threads);
    for (int run = 0; run < 5; ++run) EXPECT_EQ(chunked_sum(v, 4096), serial) << threads << " threads";
  }
  // The chunk partials are folded left to right, as a serial loop over chunks would.
  float by_hand = 0.0f;
  for (std::size_t b = 0; b < v.size(); b += 4096) {
    float s = 0.0f;
    for (std::size_t i = b; i < std::min(v.size(), b + 4096); ++i) s += v[i];
    by_hand += s;
  }
  EXPECT_EQ(serial, by_hand);
}

TEST(Parallel, UsesMoreThanOneThreadWhenAllowed) {
  ThreadCountGuard guard(2);
  ASSERT_EQ(thread_count(), 2u);
  std::atomic<int> inside{0}, overlap{0};
  std::vector<std::thread::id> ids(64);
  parallel_for(64, 1, [&](std::size_t b, std::size_t) {
    if (++inside > 1) ++overlap;
    ids[b] = std::this_thread::get_id();
    // Long enough that the second thread picks up a chunk meanwhile.
    volatile double x = 0.0;
    for (int i = 0; i < 200000; ++i) x = x + std::sqrt(double(i));
    --inside;
  });
  std::sort(ids.begin(), ids.end());
  EXPECT_GT(std::unique(ids.begin(), ids.end()) - ids.begin(), 1);
}

TEST(Parallel, NestedCallsRunInline) {
  ThreadCountGuard guard(2);
  std::vector<long> sums(8, 0);
  parallel_for(8, 1, [&](std::size_t b, std::size_t) {
    sums[b] = parallel_reduce(
        1000, 10, 0L,
        [](std::size_t s, std::size_t e) {
          long x = 0;
          for (std::size_t i = s; i < e; ++i) x += long(i);
          return x;
        },
        [](long a, long c) { return a + c; });
  });
  for (long s : sums) EXPECT_EQ(s, 999L * 1000L / 2L);
}

TEST(Parallel, ExceptionReachesTheCallerAndThePoolStaysUsable) {
  ThreadCountGuard guard(2);
  EXPECT_THROW(parallel_for(100, 1,
                            [](std::size_t b, std::size_t) {
                              if (b == 37) throw std::runtime_error("chunk 37");
                            }),
               std::runtime_error);
  std::vector<int> hits(1000, 0);
  parallel_for(hits.size(), 10, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) hits[i] = 1;
  });
  EXPECT_EQ(std::accumulate(hits.begin(), hits.end(), 0), 1000);
}

TEST(Parallel, InvokeRunsEveryTask) {
  ThreadCountGuard guard(2);
  std::vector<int> done(5, 0);
  std::vector<std::function<void()>> tasks;
  for (int i = 0; i < 5; ++i) tasks.push_back([&done, i] { done[i] = i + 1; });
  parallel_invoke(tasks);
  EXPECT_EQ(done, (std::vector<int>{1, 2, 3, 4, 5}));
}

// group_by_key is a stable counting sort: every key's items in increasing order, whatever the
// thread count, for key counts below, at and past its 256 ranges and items past one chunk.
TEST(Parallel, GroupByKeyIsAStableCountingSortForAnyThreadCount) {
  for (const std::size_t keys : {std::size_t(1), std::size_t(5), std::size_t(256), std::size_t(70001)}) {
    for (const std::size_t n : {std::size_t(0), std::size_t(7), std::size_t(300000)}) {
      std::vector<std::uint32_t> key(n);
      std::uint64_t state = 12345 + keys + n;
      for (auto& k : key) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        k = static_cast<std::uint32_t>((state >> 33) % keys);
      }
      std::vector<std::uint32_t> expected(n);
      std::iota(expected.begin(), expected.end(), 0u);
      std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
      for (const std::size_t threads : {1, 2, 3, 8}) {
        ThreadCountGuard guard(threads);
        const detail::Groups g = detail::group_by_key(n, keys, [&](std::size_t i) { return key[i]; });
        ASSERT_EQ(g.start.size(), keys + 1);
        EXPECT_TRUE(std::equal(g.items.begin(), g.items.end(), expected.begin(), expected.end())) << keys << " " << n;
        for (std::size_t k = 0; k < keys; ++k) {
          ASSERT_LE(g.start[k], g.start[k + 1]);
          for (std::uint32_t j = g.start[k]; j < g.start[k + 1]; ++j) ASSERT_EQ(key[g.items[j]], k);
        }
        EXPECT_EQ(g.start[keys], n);
      }
    }
  }
}

TEST(Parallel, ThreadCountIsAtLeastOne) {
  ThreadCountGuard guard(0);
  EXPECT_EQ(thread_count(), 1u);
}

}  // namespace
}  // namespace deepcut
