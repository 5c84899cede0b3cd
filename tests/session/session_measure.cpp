// SPDX-License-Identifier: MIT
// deepcut_session_measure: memory and time per small drill, tear and cut through Session::apply
// on a generated cactus (default 1M triangles), and per undo and redo, as the studio runs them.
// Memory is the growth of the resident set per operation (what the undo stack and the model
// keep); it uses only the Session calls every version has, so the same source measures the
// immutable-snapshot session it replaced. Not a test: no assertions, numbers on stdout.
//   deepcut_session_measure [TRIANGLES] [DRILLS]
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/process_memory.h"
#include "resident.h"
#include "session.h"

namespace {

using namespace deepcut;

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

struct Box {
  glm::vec3 c{0.0f};
  float size = 1.0f, depth = 1.0f, height = 1.0f;
};

Operation drill(const Box& b, float dy) {
  DrillOperation d;
  const glm::vec3 c = b.c + glm::vec3(0.0f, dy * b.size, 0.0f);
  d.cylinder = {c - glm::vec3(0.0f, 0.0f, b.size), c + glm::vec3(0.0f, 0.0f, b.size), 0.004f * b.size};
  d.options.wall = false;
  return Operation{d, -1, 0.0f};
}

Operation tear(const Box& b, float dx) {
  const glm::vec3 d(0.0f, 0.0f, -1.0f), up(0.0f, 1.0f, 0.0f);
  const glm::vec3 c = b.c + glm::vec3(dx * b.size, 0.0f, 0.0f);
  TearOperation t;
  const float h = 0.02f * b.height;
  t.start = {c - 1.5f * b.depth * d + h * up, c + h * up};
  t.end = {c - 1.5f * b.depth * d - h * up, c - h * up};
  return Operation{t, -1, 0.0f};
}

Operation cut(const Box& b, float dy) {
  CutOperation c;
  c.plane = {b.c + glm::vec3(0.0f, dy * b.size, 0.0f), {0.0f, 1.0f, 0.0f}};
  return Operation{c, -1, 0.0f};
}

void run(session::Session& s, const char* what, const std::vector<Operation>& ops) {
  double ms = 0.0, grown = 0.0;
  int ok = 0;
  for (const Operation& op : ops) {
    const double before = test::resident_mib();
    const auto start = std::chrono::steady_clock::now();
    const bool applied = s.apply(op).result.status == OpStatus::Ok;
    const double t = ms_since(start);
    if (!applied) continue;
    ++ok;
    ms += t;
    grown += test::resident_mib() - before;
  }
  std::printf("%-6s x%2d applied: %8.1f ms/op  %+8.2f MB resident/op\n", what, ok, ok ? ms / ok : 0.0,
              ok ? grown / ok : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();  // as the studio and the CLI run
  const std::size_t triangles = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 1000000;
  const int drills = argc > 2 ? std::atoi(argv[2]) : 10;
  CactusOptions options;
  options.target_triangles = triangles;
  Model model = make_cactus(options);
  reserve_for_operations(model);
  BoundingBox box;
  {
    const PosedModel rest = PosedModel::build(model, -1, 0.0f);
    for (const auto& [key, m] : rest.instances()) box.add(m.bounds);
  }
  Box b{0.5f * (box.min + box.max), box.diagonal(), 0.5f * (box.max.z - box.min.z), box.max.y - box.min.y};
  session::Session s;
  s.open(std::make_shared<const Model>(std::move(model)));
  s.refresh_posed_model(-1, 0.0f);
  std::size_t model_bytes = 0;
  for (const Mesh& m : s.current()->meshes)
    for (const Primitive& p : m.primitives) model_bytes += p.mesh.capacity_bytes();
  std::printf("cactus %zu triangles: the model's arrays %.1f MB, resident after open %.1f MB\n", triangles,
              static_cast<double>(model_bytes) / (1024.0 * 1024.0), test::resident_mib());
  const double start_mb = test::resident_mib();
  std::vector<Operation> ds, ts;
  for (int i = 0; i < drills; ++i) ds.push_back(drill(b, -0.3f + 0.6f * static_cast<float>(i) / static_cast<float>(drills)));
  for (int i = 0; i < drills; ++i) ts.push_back(tear(b, -0.04f + 0.08f * static_cast<float>(i) / static_cast<float>(drills)));
  run(s, "drill", ds);
  run(s, "tear", ts);
  run(s, "cut", {cut(b, 0.35f)});
  std::size_t steps = s.undo_count();
  double ms = 0.0;
  for (std::size_t i = 0; i < steps; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    s.undo();
    ms += ms_since(t0);
  }
  std::printf("undo   x%2zu: %8.1f ms/step (cut included)\n", steps, steps ? ms / static_cast<double>(steps) : 0.0);
  ms = 0.0;
  for (std::size_t i = 0; i < steps; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    s.redo();
    ms += ms_since(t0);
  }
  std::printf("redo   x%2zu: %8.1f ms/step (cut included)\n", steps, steps ? ms / static_cast<double>(steps) : 0.0);
  std::printf("resident growth over the session: %+.1f MB\n", test::resident_mib() - start_mb);
  return 0;
}
