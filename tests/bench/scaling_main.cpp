// SPDX-License-Identifier: MIT
// deepcut_scaling: how the whole-mesh passes scale with the thread count.
//
// For each size it generates the project's cactus (no data files: the program is meant to be
// copied alone to a many-core machine), writes it as a .glb into $TMPDIR, and times every pass
// that touches the whole mesh with 1, 2, 4, ... threads (the pool's `set_thread_count`): read and
// decode, the weld, posing, the cut kernel (`cut_mesh`: classification and split), the
// model-level cut (`apply_operation`, as the CLI and the studio run it), the spatial index build,
// the soft-body clustering and the export. Each time is the median of `--runs` runs. It prints a
// table with the speed-up against one thread and the same as JSON, and checks that every thread
// count produced the same bytes (a hash of each pass's output).
//
// The JSON also gives each cell's CPU time (`cpu_ms`, the whole process) and the calling thread's
// (`main_cpu_ms`), medians like `ms`, and from them `serial_ms`: with T threads, a pass whose
// serial part S runs on the calling thread and whose parallel part P is shared evenly has
// main = S + P / T and cpu = S + P, so S = (T * main - cpu) / (T - 1). Amdahl's law then bounds
// the speed-up at 1 / (s + (1 - s) / T) for the serial fraction s; these hold on a busy machine,
// where wall times do not.
//
// Links deepcut_core only (no VTK, Qt or Google Benchmark), so it can be linked statically
// (-DDEEPCUT_STATIC_SCALING=ON).

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/process_memory.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/weld.h"

namespace {

using namespace deepcut;
using Clock = std::chrono::steady_clock;
constexpr std::uint64_t kSeed = 1469598103934665603ull;

// A hash of bytes, continued from `h` (eight bytes a step; untimed, but 4M meshes are large).
std::uint64_t hash_bytes(const void* data, std::size_t n, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = (h ^ w) * 0x9e3779b97f4a7c15ull;
    h ^= h >> 31;
  }
  for (; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}
template <class T, class A>
std::uint64_t hash_vec(const std::vector<T, A>& v, std::uint64_t h) {
  return hash_bytes(v.data(), v.size() * sizeof(T), hash_bytes(&h, 0, h) ^ v.size());
}

std::uint64_t hash_attrs(const AttributeSet& set, std::uint64_t h) {
  for (const auto& name : set.names()) {
    const AttributeArrayBase* a = set.base(name);
    h = hash_bytes(name.data(), name.size(), h);
    if (a->size() > 0) h = hash_bytes(a->element_data(0), a->size() * a->element_bytes(), h);
  }
  return h;
}

std::uint64_t hash_mesh(const SurfaceMesh& m, std::uint64_t h) {
  h = hash_vec(m.positions(), h);
  h = hash_vec(m.faces(), h);
  h = hash_attrs(m.vertex_attrs(), h);
  h = hash_attrs(m.corner_attrs(), h);
  return hash_attrs(m.face_attrs(), h);
}

std::uint64_t hash_model(const Model& model) {
  std::uint64_t h = kSeed;
  for (const auto& mesh : model.meshes)
    for (const auto& prim : mesh.primitives) h = hash_mesh(prim.mesh, h);
  return h;
}

std::uint64_t hash_clusters(const Clusters& c, std::size_t vertices) {
  std::uint64_t h = kSeed;
  for (std::uint32_t v = 0; v < vertices; ++v)
    for (const Influence& in : c.influences(VertexId(v))) h = hash_bytes(&in, sizeof(in), h);
  for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
    h = hash_vec(c.members(p), h);
    h = hash_bytes(&c.rest_centre(p), sizeof(glm::vec3), h);
  }
  return h;
}

std::vector<unsigned char> read_all(const std::string& path) {
  std::vector<unsigned char> out;
  if (FILE* f = std::fopen(path.c_str(), "rb")) {
    unsigned char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof(buf), f)) > 0) out.insert(out.end(), buf, buf + n);
    std::fclose(f);
  }
  return out;
}

struct Options {
  std::vector<std::size_t> sizes = {1000000, 4000000};
  std::vector<std::size_t> threads = {1, 2, 4, 8, 16};
  std::vector<std::string> passes;  // empty: all
  int runs = 3;
  std::string json_path;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

std::size_t parse_count(const std::string& s) {
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  if (end && (*end == 'M' || *end == 'm')) v *= 1e6, ++end;
  else if (end && (*end == 'K' || *end == 'k')) v *= 1e3, ++end;
  if (!end || *end != '\0' || !(v >= 1.0)) {
    std::cerr << "deepcut_scaling: bad number '" << s << "'\n";
    std::exit(2);
  }
  return static_cast<std::size_t>(v);
}

void usage() {
  std::cout << "usage: deepcut_scaling [--sizes 1M,4M] [--threads 1,2,4,8,16] [--runs 3] [--passes a,b]\n"
               "                       [--json FILE]\n"
               "Times the whole-mesh passes (read, weld, pose, cut_mesh, cut_model, index, cluster,\n"
               "export) on a generated cactus for each thread count; medians of --runs runs. The\n"
               "temporary .glb goes into $TMPDIR (default /tmp). Prints a table, then JSON (also\n"
               "written to FILE with --json). Exit 1 when thread counts gave different bytes.\n";
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "deepcut_scaling: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      usage();
      std::exit(0);
    } else if (a == "--sizes") {
      o.sizes.clear();
      for (const auto& s : split(next())) o.sizes.push_back(parse_count(s));
    } else if (a == "--threads") {
      o.threads.clear();
      for (const auto& s : split(next())) o.threads.push_back(parse_count(s));
    } else if (a == "--runs") {
      o.runs = static_cast<int>(parse_count(next()));
    } else if (a == "--passes") {
      o.passes = split(next());
    } else if (a == "--json") {
      o.json_path = next();
    } else {
      std::cerr << "deepcut_scaling: unknown argument '" << a << "' (see --help)\n";
      std::exit(2);
    }
  }
  return o;
}

// One pass: `prepare` runs untimed before each run, `run` is timed, `digest` (untimed) hashes
// what it made.
struct Pass {
  std::string name;
  std::function<void()> prepare;
  std::function<void()> run;
  std::function<std::uint64_t()> digest;
};

struct Cell {
  double ms = 0.0;
  std::uint64_t hash = 0;
  double cpu_ms = 0.0, main_cpu_ms = 0.0;  // the process's and the calling thread's CPU time
};

double cpu_ms(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) / 1e6;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// The state the passes share for one size.
struct Fixture {
  std::string glb, out;
  Model welded;          // as read (welded): pose, cut, index, cluster, export work on it
  SurfaceMesh unwelded;  // the first primitive read without the weld (its input)
  ClusterOptions cluster;
  Plane plane;
  // What the passes make (filled by `run`, hashed by `digest`).
  SurfaceMesh scratch;
  Model scratch_model;
  PosedModel posed;
  TriangleGrid grid;
  Clusters clusters;
  std::size_t count = 0;
};


const SurfaceMesh& first_mesh(const Model& m) { return m.meshes.at(0).primitives.at(0).mesh; }

std::vector<Pass> make_passes(Fixture& fx) {
  auto none = [] {};
  auto model_digest = [&fx] { return hash_model(fx.scratch_model); };
  auto mesh_digest = [&fx] { return hash_mesh(fx.scratch, fx.count); };
  std::vector<Pass> passes;
  passes.push_back({"read", none, [&fx] {
                      ImportOptions o;
                      o.weld = false;  // still renumbers the vertices (WeldKey::None), a light pass
                      fx.scratch_model = read_gltf(fx.glb, o);
                    }, model_digest});
  passes.push_back({"read+weld", none, [&fx] { fx.scratch_model = read_gltf(fx.glb); }, model_digest});
  passes.push_back({"weld", [&fx] { fx.scratch = fx.unwelded; },
                    [&fx] { fx.count = weld(fx.scratch, {WeldKey::PositionAndSkin}).merged; }, mesh_digest});
  passes.push_back({"pose", none,
                    [&fx] {
                      const int anim = fx.welded.animations.empty() ? -1 : 0;
                      fx.posed = PosedModel::build(fx.welded, anim, 0.7f, PoseDetail::Positions);
                    },
                    [&fx] {
                      std::uint64_t h = kSeed;
                      for (const auto& [key, inst] : fx.posed.instances()) h = hash_vec(inst.linear, hash_vec(inst.posed, h));
                      return h;
                    }});
  passes.push_back({"cut_mesh", [&fx] { fx.scratch = first_mesh(fx.welded); },
                    [&fx] { fx.count = cut_mesh(fx.scratch, fx.scratch.positions(), fx.plane).intersection_points; },
                    mesh_digest});
  passes.push_back({"cut_model",
                    [&fx] {
                      fx.scratch_model = fx.welded;
                      // As `deepcut apply` and the studio hold a model: room reserved to grow.
                      reserve_for_operations(fx.scratch_model);
                      fx.posed = PosedModel::build(fx.scratch_model, -1, 0.0f, PoseDetail::Positions);
                    },
                    [&fx] {
                      Operation op;
                      op.params = CutOperation{fx.plane, {}};
                      apply_operation(fx.scratch_model, op, fx.posed);
                    },
                    model_digest});
  passes.push_back({"index", none,
                    [&fx] {
                      const SurfaceMesh& m = first_mesh(fx.welded);
                      fx.grid = TriangleGrid::build(m, m.positions());
                    },
                    [&fx] { return fx.grid.layout_hash(); }});
  passes.push_back({"cluster", none,
                    [&fx] {
                      const SurfaceMesh& m = first_mesh(fx.welded);
                      fx.clusters = Clusters::build(m, m.positions(), fx.cluster);
                    },
                    [&fx] { return hash_clusters(fx.clusters, first_mesh(fx.welded).vertex_count()); }});
  passes.push_back({"export", none, [&fx] { write_gltf(fx.welded, fx.out); },
                    [&fx] { return hash_vec(read_all(fx.out), kSeed); }});
  return passes;
}

Fixture make_fixture(std::size_t triangles, const std::string& dir) {
  Fixture fx;
  const std::string stem = dir + "/deepcut_scaling_" + std::to_string(::getpid()) + "_" + std::to_string(triangles);
  fx.glb = stem + ".glb";
  fx.out = stem + "_out.glb";
  CactusOptions co;
  co.target_triangles = triangles;
  write_gltf(make_cactus(co), fx.glb);
  fx.welded = read_gltf(fx.glb);
  ImportOptions raw;
  raw.weld = false;
  fx.unwelded = first_mesh(read_gltf(fx.glb, raw));
  const SurfaceMesh& m = first_mesh(fx.welded);
  // The bench's soft body: the radius giving the paper's 224 particles on the 25k cactus.
  fx.cluster.radius = radius_for_particle_count(first_mesh(make_cactus()), first_mesh(make_cactus()).positions(), 224);
  const BoundingBox box = m.bounds();
  fx.plane.point = 0.5f * (box.min + box.max);
  fx.plane.normal = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f));
  return fx;
}

bool wanted(const Options& o, const std::string& pass) {
  return o.passes.empty() || std::find(o.passes.begin(), o.passes.end(), pass) != o.passes.end();
}

std::string fmt(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  deepcut::keep_freed_memory();  // an operation writes into the pages the last one freed
  const Options opt = parse(argc, argv);
  const char* tmp = std::getenv("TMPDIR");
  const std::string dir = tmp && *tmp ? tmp : "/tmp";
  bool identical = true;
  std::ostringstream json;
  json << "{\n  \"hardware_threads\": " << std::thread::hardware_concurrency() << ",\n  \"runs\": " << opt.runs
       << ",\n  \"results\": [";
  bool first_json = true;
  for (const std::size_t size : opt.sizes) {
    std::cerr << "deepcut_scaling: generating the cactus (" << size << " triangles) in " << dir << "\n";
    set_thread_count(opt.threads.empty() ? 1 : *std::max_element(opt.threads.begin(), opt.threads.end()));
    Fixture fx = make_fixture(size, dir);
    const std::size_t triangles = first_mesh(fx.welded).face_count();
    std::vector<Pass> passes = make_passes(fx);
    std::map<std::string, std::vector<Cell>> cells;
    for (const std::size_t t : opt.threads) {
      set_thread_count(t);
      for (auto& pass : passes) {
        if (!wanted(opt, pass.name)) continue;
        std::vector<double> times, cpu, main_cpu;
        std::uint64_t hash = 0;
        for (int r = 0; r < std::max(opt.runs, 1); ++r) {
          pass.prepare();
          const double p0 = cpu_ms(CLOCK_PROCESS_CPUTIME_ID), m0 = cpu_ms(CLOCK_THREAD_CPUTIME_ID);
          const auto t0 = Clock::now();
          pass.run();
          times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
          cpu.push_back(cpu_ms(CLOCK_PROCESS_CPUTIME_ID) - p0);
          main_cpu.push_back(cpu_ms(CLOCK_THREAD_CPUTIME_ID) - m0);
          hash = pass.digest();
        }
        cells[pass.name].push_back({median(times), hash, median(cpu), median(main_cpu)});
      }
    }
    std::remove(fx.glb.c_str());
    std::remove(fx.out.c_str());
    std::cout << "\n" << triangles << " triangles (threads: ms, speed-up against " << opt.threads.front() << ")\n";
    std::cout << "pass        ";
    for (const std::size_t t : opt.threads) std::cout << "  " << t << " thr ms   x  ";
    std::cout << " same bytes\n";
    for (const auto& pass : passes) {
      if (!cells.count(pass.name)) continue;
      const auto& row = cells[pass.name];
      bool same = true;
      for (const auto& c : row) same = same && c.hash == row.front().hash;
      identical = identical && same;
      std::string name = pass.name;
      name.resize(12, ' ');
      std::cout << name;
      for (const auto& c : row) std::cout << "  " << fmt(c.ms, 1) << "  " << fmt(row.front().ms / c.ms, 2) << "x";
      std::cout << "  " << (same ? "yes" : "NO") << "\n";
      json << (first_json ? "\n" : ",\n") << "    {\"triangles\": " << triangles << ", \"pass\": \"" << pass.name
           << "\", \"identical\": " << (same ? "true" : "false") << ", \"by_threads\": [";
      first_json = false;
      for (std::size_t i = 0; i < row.size(); ++i) {
        const double t = double(opt.threads[i]);
        const double serial = t > 1 ? std::max(0.0, (t * row[i].main_cpu_ms - row[i].cpu_ms) / (t - 1)) : row[i].cpu_ms;
        json << (i ? ", " : "") << "{\"threads\": " << opt.threads[i] << ", \"ms\": " << fmt(row[i].ms, 3)
             << ", \"speedup\": " << fmt(row.front().ms / row[i].ms, 3) << ", \"cpu_ms\": " << fmt(row[i].cpu_ms, 3)
             << ", \"main_cpu_ms\": " << fmt(row[i].main_cpu_ms, 3) << ", \"serial_ms\": " << fmt(serial, 3) << "}";
      }
      json << "]}";
    }
  }
  json << "\n  ],\n  \"identical\": " << (identical ? "true" : "false") << "\n}\n";
  std::cout << "\n" << json.str();
  if (!opt.json_path.empty()) {
    if (FILE* f = std::fopen(opt.json_path.c_str(), "w")) {
      std::fputs(json.str().c_str(), f);
      std::fclose(f);
    }
  }
  if (!identical) std::cerr << "deepcut_scaling: thread counts gave different bytes\n";
  return identical ? 0 : 1;
}
