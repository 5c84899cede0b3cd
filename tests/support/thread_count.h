// SPDX-License-Identifier: MIT
#pragma once
// Runs a scope with the core pool at a given size and restores the size it had (tests that
// compare results across thread counts).

#include <cstddef>

#include "deepcut/core/parallel.h"

namespace deepcut::test {

class ThreadCount {
 public:
  explicit ThreadCount(std::size_t n) : saved_(thread_count()) { set_thread_count(n); }
  ~ThreadCount() { set_thread_count(saved_); }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  std::size_t saved_;
};

}  // namespace deepcut::test
