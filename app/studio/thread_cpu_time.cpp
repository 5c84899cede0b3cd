// SPDX-License-Identifier: MIT
#include "thread_cpu_time.h"

#include <ctime>

#if defined(_WIN32)
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#ifndef NOMINMAX
#define NOMINMAX
#endif
#include <windows.h>  // GetThreadTimes
#include <cstdint>
#else
#include <sys/resource.h>  // getrusage
#endif

namespace deepcut::studio {

double thread_cpu_ms() {
#if defined(_WIN32)
  FILETIME created, exited, kernel, user;
  if (GetThreadTimes(GetCurrentThread(), &created, &exited, &kernel, &user)) {
    auto ticks = [](const FILETIME& t) {
      return (static_cast<std::uint64_t>(t.dwHighDateTime) << 32) | t.dwLowDateTime;
    };
    return static_cast<double>(ticks(kernel) + ticks(user)) / 1e4;  // 100 ns units
  }
#elif defined(CLOCK_THREAD_CPUTIME_ID)
  timespec t{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t) == 0)
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
#endif
  return 1e3 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

long process_minor_faults() {
#if defined(_WIN32)
  return 0;
#else
  rusage usage{};
  return getrusage(RUSAGE_SELF, &usage) == 0 ? usage.ru_minflt : 0;
#endif
}

}  // namespace deepcut::studio
