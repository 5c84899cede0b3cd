// SPDX-License-Identifier: MIT
// deepcut_bench: runs the Google Benchmark cases and prints, per case and size, our median time,
// the peer's median measured in the same run on the same mesh, and the ratio peer / ours.
//   deepcut_bench [--json] [--quick] [--benchmark_* flags]
// --quick skips the ~1M-triangle cases (CTest label `bench` uses it).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_cases.h"
#include "deepcut/core/process_memory.h"

namespace {

using nlohmann::json;

// Collects the median of each benchmark's repetitions.
class Collector : public benchmark::BenchmarkReporter {
 public:
  struct Row {
    double ms = 0;
    double triangles = 0;
    double touched = -1;  // triangles a local edit replaced (drill, tear), -1 when not reported
  };
  std::map<std::string, Row> medians;

  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& run : runs) {
      if (run.run_type != Run::RT_Aggregate || run.aggregate_name != "median") continue;
      std::string name = run.run_name.function_name;
      Row row;
      row.ms = run.GetAdjustedRealTime();  // in the benchmark's unit: milliseconds
      auto it = run.counters.find("triangles");
      if (it != run.counters.end()) row.triangles = it->second.value;
      auto touched = run.counters.find("touched");
      if (touched != run.counters.end()) row.touched = touched->second.value;
      medians[name] = row;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  deepcut::keep_freed_memory();  // an operation writes into the pages the last one freed
  bool as_json = false, quick = false;
  std::vector<char*> args = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--json") == 0) as_json = true;
    else if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    else args.push_back(argv[i]);
  }
  std::string reps = "--benchmark_repetitions=5";
  args.push_back(reps.data());
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  deepcut::bench::register_cases(!quick);
  Collector collector;
  benchmark::RunSpecifiedBenchmarks(&collector);

  // Pair "<case>/ours/<size>" with "<case>/<peer>/<size>".
  struct Case {
    std::string name, size, peer;
    double triangles = 0, ours_ms = 0, peer_ms = 0, touched = -1;
  };
  std::map<std::pair<std::string, std::string>, Case> cases;
  for (const auto& [full, row] : collector.medians) {
    const auto a = full.find('/'), b = full.rfind('/');
    const std::string name = full.substr(0, a), impl = full.substr(a + 1, b - a - 1), size = full.substr(b + 1);
    Case& c = cases[{name, size}];
    c.name = name;
    c.size = size;
    c.triangles = row.triangles;
    if (impl == "ours") {
      c.ours_ms = row.ms;
      c.touched = row.touched;
    } else {
      c.peer = impl;
      c.peer_ms = row.ms;
    }
  }
  const auto quoted = deepcut::bench::quoted_figures();
  const auto memory = quick ? deepcut::bench::MemoryReport{} : deepcut::bench::measure_cut_memory();

  json out = {{"cases", json::array()}};
  for (const auto& [key, c] : cases) {
    json j = {{"name", c.name}, {"size", c.size}, {"triangles", c.triangles}, {"ours_ms", c.ours_ms}};
    if (c.touched >= 0) j["touched_triangles"] = c.touched;
    if (!c.peer.empty()) {
      j["peer"] = c.peer;
      j["peer_ms"] = c.peer_ms;
      j["ratio"] = c.ours_ms > 0 ? c.peer_ms / c.ours_ms : 0.0;
    }
    for (const auto& q : quoted)
      if (q.name == c.name && c.size == "25k") {
        j["paper_ms"] = q.paper_ms;
        j["paper_note"] = q.note;
      }
    out["cases"].push_back(j);
  }
  if (!quick)
    out["cases"].push_back({{"name", "cut_peak_memory"},
                            {"size", "1M"},
                            {"triangles", memory.triangles},
                            {"mesh_mb", memory.mesh_mb},
                            {"extra_peak_mb", memory.extra_peak_mb},
                            {"ratio_to_mesh", memory.ratio}});
  if (as_json) {
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("\n%-14s %-5s %10s %12s %-22s %12s %9s %12s %8s\n", "case", "size", "triangles", "ours ms", "peer", "peer ms",
              "ratio", "paper ms", "touched");
  for (const auto& j : out["cases"]) {
    if (j["name"] == "cut_peak_memory") continue;
    std::printf("%-14s %-5s %10.0f %12.3f %-22s %12s %9s %12s %8s\n", j["name"].get<std::string>().c_str(),
                j["size"].get<std::string>().c_str(), j["triangles"].get<double>(), j["ours_ms"].get<double>(),
                j.value("peer", std::string("-")).c_str(),
                j.contains("peer_ms") ? std::to_string(j["peer_ms"].get<double>()).c_str() : "-",
                j.contains("ratio") ? (std::to_string(j["ratio"].get<double>()).substr(0, 6) + "x").c_str() : "-",
                j.contains("paper_ms") ? std::to_string(j["paper_ms"].get<double>()).c_str() : "-",
                j.contains("touched_triangles") ? std::to_string(j["touched_triangles"].get<long long>()).c_str() : "-");
  }
  if (!quick)
    std::printf("\ncut peak memory on %zu triangles: mesh %.1f MB, cut adds %.1f MB at peak: %.2fx the mesh's own size\n",
                memory.triangles, memory.mesh_mb, memory.extra_peak_mb, memory.ratio);
  std::printf("paper figures are quoted from its Tables 1 and 2 (i7-7700HQ), not measured here.\n");
  return 0;
}
