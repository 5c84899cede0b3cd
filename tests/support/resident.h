// SPDX-License-Identifier: MIT
#pragma once
// The process's resident memory, for tests and benchmarks that measure what an operation or a
// session keeps (Linux: /proc/self/statm; 0 where it cannot be read).

#include <unistd.h>

#include <fstream>

namespace deepcut::test {

/// Resident memory now, in MiB.
inline double resident_mib() {
  std::ifstream in("/proc/self/statm");
  long pages = 0, resident = 0;
  in >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace deepcut::test
