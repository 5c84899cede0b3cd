// SPDX-License-Identifier: MIT
// deepcut_studio_bench: what a studio user waits for, on the generated cactus (about 25K and 1M
// triangles), measured through the main window as the user drives it (needs a display: run it
// under xvfb-run, or through `deepcut bench --studio`):
// - open: the glTF file opened to the first render call, and to the first frame drawn (then
//   the operations' posed model is built off the UI thread: "operations ready");
// - a small drill, a tear and a cut applied (operation, undo record, scene, VTK data and
//   inspector update): from Apply to the render call, and to the frame drawn;
// - the undo and the redo of each, likewise;
// - an unchanged re-render beside them (the floor a frame costs on this renderer), also
//   multisampled (View > Anti-aliasing > Multisampling);
// - the same steps with the scene built again after each (DEEPCUT_VIEW_REBUILD=1, rows
//   "..._rebuild"): the reference the incremental view is measured against, in the same run;
// - resident memory after N small drills (growth per operation).
// Beside the wall times: the UI thread's CPU time in the first frame and in an unchanged one
// ("frame_ui_cpu_ms"; the renderer's own threads not counted), steadier on a loaded machine; from
// the action to its render call, the UI thread's CPU time ("to_render_call_ui_cpu_ms") and the
// whole process's (every thread of the pool, "to_render_call_process_cpu_ms"), and the process's
// minor page faults ("to_render_call_minor_faults": fresh memory, whose cost on some machines
// instruction counts do not show; for an apply also split as its phases are). An operation's
// apply also says where its time to the render call went ("phases": the operation with its undo
// record, the scene following it, the view's VTK data, the last two also as the process's CPU
// time; none for the "..._rebuild" rows but the operation's), the bytes its undo step holds once
// made ("undo_record_bytes": what the session keeps to take it back, beside the steps the apply
// keeps; the median of the repetitions) and what it left for when the UI is idle
// after its frame ("prepare_updates_ms": SceneView::prepare_updates, the corner lists of a cut's
// pieces, timed on its own before the undo so that the undo does not pay for it), and each of
// the three applies on its own ("runs": the first takes fresh memory, the later ones the memory of
// the step the one before undid).
//   deepcut_studio_bench [--json] [--quick] [--size N] [--no-rebuild] [--ops N] [--cuts N]
//                        [--session N] [--open-only] [--only drill|tear|cut]
// --quick: the 25K cactus only; --size N: only the cactus of about N triangles (a profile of one
// size); --no-rebuild: without the "..._rebuild" rows; --open-only: the open and the unchanged
// re-renders only (a profile of the open); --only KIND: of the operations, only that kind's
// apply, undo and redo (a profile of one operation; `--ops 0` skips the memory run too);
// --cuts N: after the drills' memory run, N cuts each undone, across the middle and at the tip
// by turns, and the resident memory before and after ("cut_undo_memory": what the pieces an
// undo set aside and the spares they are made into keep alive over a long session).
// --session N (default off): right after the open's rows, N operations as a designer applies them
// over a session, none undone: small drills, tears and cuts (both sides kept) by turns, placed as
// above (a miss is placed again, untimed); then the run for that size ends (the other rows would
// time a model cut N times). "session" reports how many "drills", "tears" and "cuts" were made (and
// "misses" placed again), and in "start" (the session's start, after the open and its re-renders,
// once the studio has been idle MainWindow::kIdleReleaseMs), "after" (right after the N
// operations) and "after_idle" (then idle as at the start: the studio has handed the heap's free
// memory back, MainWindow::release_when_idle): "primitives" (the model's), "model_bytes" (what the model's
// meshes hold: over every primitive's SurfaceMesh, its face slots' corners and deleted marks and
// every vertex, face and corner attribute, size times element bytes, capacity not counted; skins,
// animations and images not counted) and "model_capacity_bytes" (the same arrays' capacity: room
// reserved included); "undo_bytes" (Session::undo_bytes after the N: what the undo steps keep);
// "view_bytes" and "view_used_bytes" (SceneView::data_bytes: what the view's data, drawn and set
// aside, holds and uses);
// "resident_mib" (/proc/self/statm) and "heap_free_mib" (glibc mallinfo2 fordblks: freed memory the
// heap keeps for reuse, resident or not; -1 elsewhere); and "resident_growth_over_model": (resident
// after N less resident at the start) / model_bytes at the start, the issue's "a long session
// within 2x the model's own memory" (what the session costs beyond what the open held, against the
// model opened; the open's own baseline, Qt, VTK and the view's data, is not the session's), beside
// "resident_after_over_start" (the whole process, after over before), and "idle_growth_over_model"
// (the same growth with "after_idle": what a long session leaves once the user pauses).
// Medians of three repetitions for each timed step.
#include <malloc.h>
#include <unistd.h>

#include <QAction>
#include <QApplication>
#include <QDir>
#include <QTemporaryDir>
#include <QUndoStack>
#include <QtTest/QtTest>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/process_memory.h"
#include "main_window.h"
#include "resident.h"
#include "scene_host.h"
#include "scene_view.h"
#include "thread_cpu_time.h"

namespace {

using Clock = std::chrono::steady_clock;
using deepcut::studio::MainWindow;
using deepcut::test::resident_mib;
using nlohmann::json;

double ms_since(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double, std::milli>(t1 - t0).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// CPU time of the whole process (every thread), in ms.
double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

/// Times one action in the window: to the first render call it makes, and to its return (the
/// frame drawn).
struct Timed {
  double to_render = 0.0, to_frame = 0.0;
  Clock::time_point start;
  double frame_cpu = 0.0;  // the UI thread's CPU time in the last frame drawn (SceneView)
  double ui_cpu = 0.0, process_cpu = 0.0;  // CPU time to the render call: the UI thread's, every thread's
  long faults_at_start = 0, faults = 0;    // the process's minor page faults: at the start, to the render call
};

class Timer {
 public:
  explicit Timer(MainWindow& window) : window_(window) {
    window_.view()->set_render_listener([this] {
      if (rendered_) return;
      first_render_ = Clock::now();
      render_ui_cpu_ = deepcut::studio::thread_cpu_ms();
      render_process_cpu_ = process_cpu_ms();
      render_faults_ = deepcut::studio::process_minor_faults();
      rendered_ = true;
    });
  }
  ~Timer() { window_.view()->set_render_listener(nullptr); }
  template <class Action>
  Timed time(Action&& action) {
    rendered_ = false;
    const double ui0 = deepcut::studio::thread_cpu_ms(), process0 = process_cpu_ms();
    const long faults0 = deepcut::studio::process_minor_faults();
    const auto t0 = Clock::now();
    action();
    const auto t1 = Clock::now();
    if (!rendered_) {
      render_ui_cpu_ = deepcut::studio::thread_cpu_ms();
      render_process_cpu_ = process_cpu_ms();
      render_faults_ = deepcut::studio::process_minor_faults();
    }
    return {ms_since(t0, rendered_ ? first_render_ : t1),
            ms_since(t0, t1),
            t0,
            rendered_ ? window_.view()->last_render_cpu_ms() : 0.0,
            render_ui_cpu_ - ui0,
            render_process_cpu_ - process0,
            faults0,
            render_faults_ - faults0};
  }

 private:
  MainWindow& window_;
  bool rendered_ = false;
  Clock::time_point first_render_;
  double render_ui_cpu_ = 0.0, render_process_cpu_ = 0.0;
  long render_faults_ = 0;
};

/// Operations around the cactus' middle, at the window's pose: small drills (no wall), tears
/// and cuts, each a little apart from the last (a linear congruential sequence).
class Placer {
 public:
  explicit Placer(const MainWindow& window) : window_(window) {
    box_ = window.model()->meshes.front().primitives.front().mesh.bounds();
  }
  deepcut::Operation drill() {
    const glm::vec3 at = centre() + glm::vec3(0.0f, (next() - 0.5f) * 0.5f * size(), 0.0f);
    deepcut::DrillOperation drill;
    drill.cylinder.a = at - glm::vec3(0.0f, 0.0f, size());
    drill.cylinder.b = at + glm::vec3(0.0f, 0.0f, size());
    drill.cylinder.radius = 0.01f * size();
    return posed(drill);
  }
  deepcut::Operation tear() {
    const glm::vec3 at = centre() + glm::vec3((next() - 0.5f) * 0.2f * size(), (next() - 0.5f) * 0.4f * size(), 0.0f);
    const float depth = 0.5f * (box_.max.z - box_.min.z), height = 0.5f * (box_.max.y - box_.min.y);
    const glm::vec3 up(0.0f, 1.0f, 0.0f), handle = at + 1.5f * depth * glm::vec3(0.0f, 0.0f, 1.0f);
    deepcut::TearOperation tear;
    tear.start = {handle + 0.3f * height * up, at + 0.3f * height * up};
    tear.end = {handle - 0.3f * height * up, at - 0.3f * height * up};
    return posed(tear);
  }
  /// A cut near the top of the model (a small piece: its tip).
  deepcut::Operation tip_cut() {
    deepcut::CutOperation cut;
    cut.plane.point = centre();
    cut.plane.point.y = box_.max.y - (0.02f + 0.02f * next()) * (box_.max.y - box_.min.y);
    cut.plane.normal = glm::vec3(0.1f * (next() - 0.5f), 1.0f, 0.05f);
    return posed(cut);
  }
  deepcut::Operation cut() {
    deepcut::CutOperation cut;
    cut.plane.point = centre() + glm::vec3(0.0f, (next() - 0.5f) * 0.3f * size(), 0.0f);
    cut.plane.normal = glm::vec3(0.1f * (next() - 0.5f), 1.0f, 0.05f);
    return posed(cut);
  }

 private:
  float next() {
    state_ = state_ * 1664525u + 1013904223u;
    return static_cast<float>(state_ >> 8) / static_cast<float>(1u << 24);
  }
  glm::vec3 centre() const { return 0.5f * (box_.min + box_.max); }
  float size() const { return box_.diagonal(); }
  deepcut::Operation posed(deepcut::OperationParams params) const {
    deepcut::Operation op;
    op.params = std::move(params);
    op.animation = window_.scene()->animation;
    op.time = window_.scene()->time;
    return op;
  }
  const MainWindow& window_;
  deepcut::BoundingBox box_;
  std::uint32_t state_ = 11u;
};

/// Applies `op` as one undo step. @returns false when it missed (nothing changed).
bool apply(MainWindow& window, const deepcut::Operation& op) {
  deepcut::History history;
  history.operations.push_back(op);
  // The stack's index (not its count: a step pushed after an undo replaces the undone one).
  const int index = window.history()->index();
  window.apply_history(history, "bench");
  return window.history()->index() > index;
}

/// Bytes the arrays of one attribute set hold, capacity not counted.
std::size_t used_bytes(const deepcut::AttributeSet& attrs) {
  std::size_t bytes = 0;
  for (const std::string& name : attrs.names())
    bytes += attrs.base(name)->size() * attrs.base(name)->element_bytes();
  return bytes;
}

struct ModelBytes {
  std::size_t used = 0, capacity = 0, primitives = 0;
};

/// What the model's meshes hold: bytes in use, bytes with the room reserved (see the header).
ModelBytes model_bytes(const deepcut::Model& model) {
  ModelBytes bytes;
  for (const deepcut::Mesh& mesh : model.meshes)
    for (const deepcut::Primitive& prim : mesh.primitives) {
      ++bytes.primitives;
      const deepcut::SurfaceMesh& m = prim.mesh;
      bytes.used += m.face_slots() * (sizeof(deepcut::Triangle) + 1) + used_bytes(m.vertex_attrs()) +
                    used_bytes(m.face_attrs()) + used_bytes(m.corner_attrs());
      bytes.capacity += m.capacity_bytes();
    }
  return bytes;
}

/// Freed memory the heap keeps for reuse, in MiB (-1 where the heap does not say).
double heap_free_mib() {
#if defined(__GLIBC__)
  return static_cast<double>(mallinfo2().fordblks) / (1024.0 * 1024.0);
#else
  return -1.0;
#endif
}

/// The model's, the undo stack's and the process's memory now (the session's rows).
json memory_json(const MainWindow& window) {
  const ModelBytes model = model_bytes(*window.model());
  json out;
  out["primitives"] = model.primitives;
  out["model_bytes"] = model.used;
  out["model_capacity_bytes"] = model.capacity;
  out["undo_bytes"] = window.session().undo_bytes();
  const deepcut::studio::SceneView::DataBytes view = window.view()->data_bytes();
  out["view_bytes"] = view.held;
  out["view_used_bytes"] = view.used;
  out["resident_mib"] = resident_mib();
  out["heap_free_mib"] = heap_free_mib();
  return out;
}

/// memory_json once the studio has been idle long enough to hand its free memory back
/// (MainWindow::release_when_idle): the background task done, then the idle interval passed.
json idle_memory_json(MainWindow& window) {
  while (window.task()->busy()) QTest::qWait(20);
  QTest::qWait(MainWindow::kIdleReleaseMs + 500);
  return memory_json(window);
}

/// `count` operations none undone, small drills, tears and cuts by turns (a miss placed again).
json run_session(MainWindow& window, Placer& place, int count) {
  json out = {{"operations", count}, {"start", idle_memory_json(window)}};
  int made[3] = {0, 0, 0}, misses = 0;
  for (int i = 0; i < count; ++i) {
    const int kind = i % 3;
    while (!apply(window, kind == 0 ? place.drill() : kind == 1 ? place.tear() : place.cut()))
      if (++misses > 20 * count + 20)
        throw std::runtime_error("the session's operations keep missing the model");
    ++made[kind];
  }
  out["drills"] = made[0];
  out["tears"] = made[1];
  out["cuts"] = made[2];
  out["misses"] = misses;
  out["after"] = memory_json(window);
  const double start = out["start"]["resident_mib"], after = out["after"]["resident_mib"];
  const double model = out["start"]["model_bytes"].get<double>() / (1024.0 * 1024.0);
  out["resident_growth_over_model"] = (after - start) / model;
  out["resident_after_over_start"] = after / start;
  out["after_idle"] = idle_memory_json(window);
  out["idle_growth_over_model"] = (out["after_idle"]["resident_mib"].get<double>() - start) / model;
  return out;
}

json step_json(const std::vector<Timed>& runs) {
  std::vector<double> render, frame, cpu, ui, process, faults;
  for (const Timed& t : runs) {
    faults.push_back(static_cast<double>(t.faults));
    render.push_back(t.to_render);
    frame.push_back(t.to_frame);
    cpu.push_back(t.frame_cpu);
    ui.push_back(t.ui_cpu);
    process.push_back(t.process_cpu);
  }
  return {{"to_render_call_ms", median(render)}, {"to_frame_ms", median(frame)},
          {"frame_ui_cpu_ms", median(cpu)},      {"to_render_call_ui_cpu_ms", median(ui)},
          {"to_render_call_process_cpu_ms", median(process)}, {"to_render_call_minor_faults", median(faults)}};
}

/// Each apply in order, beside the medians: the first finds no undone step whose memory it could
/// take, the later ones take the memory of the step the one before undid.
json runs_json(const std::vector<Timed>& applied, const std::vector<double>& operation,
               const std::vector<double>& scene, const std::vector<double>& view) {
  json runs = json::array();
  for (std::size_t i = 0; i < applied.size(); ++i)
    runs.push_back({{"to_render_call_ms", applied[i].to_render},
                    {"minor_faults", applied[i].faults},
                    {"operation_ms", operation[i]},
                    {"scene_ms", scene[i]},
                    {"view_ms", view[i]}});
  return runs;
}

/// One operation kind: apply, undo and redo three times each (undone again after each redo).
json time_operation(MainWindow& window, Timer& timer, const std::function<deepcut::Operation()>& make) {
  std::vector<Timed> applied, undone, redone;
  std::vector<double> operation, scene, view, scene_cpu, view_cpu, idle;  // the apply's phases, its idle work
  std::vector<double> before_faults, scene_faults, view_faults;  // minor page faults: to the scene, in it, in the view
  std::vector<double> record;  // bytes of the apply's undo step (where no step undone was dropped)
  for (int rep = 0, misses = 0; rep < 3;) {
    const deepcut::Operation op = make();
    bool hit = false;
    // The apply drops the steps undone: what it adds to those it keeps is its own step.
    const std::size_t held = window.session().done_bytes();
    const Timed t = timer.time([&] { hit = apply(window, op); });
    if (!hit) {  // placed where the tool misses: placed again, untimed
      if (++misses > 20) throw std::runtime_error("the operations keep missing the model");
      continue;
    }
    ++rep;
    applied.push_back(t);
    const deepcut::studio::SceneHost::StepTiming step = window.scene_host()->last_step_timing();
    operation.push_back(window.last_operation_ms());
    // Signed: a step that is not exact clears the steps before it, so the bytes may drop.
    record.push_back(static_cast<double>(window.session().undo_bytes()) - static_cast<double>(held));
    scene.push_back(step.scene_ms);
    view.push_back(step.view_ms);
    scene_cpu.push_back(step.scene_cpu_ms);
    view_cpu.push_back(step.view_cpu_ms);
    // A step the scene did not follow (a rebuild) has no phases: its faults all count before.
    const long at_scene = step.faults_at_start != 0 ? step.faults_at_start : t.faults_at_start + t.faults;
    before_faults.push_back(static_cast<double>(at_scene - t.faults_at_start));
    scene_faults.push_back(static_cast<double>(step.scene_faults));
    view_faults.push_back(static_cast<double>(step.view_faults));
    const auto idle0 = Clock::now();
    window.view()->prepare_updates();  // what the step's zero timer would do after its frame
    idle.push_back(ms_since(idle0, Clock::now()));
    undone.push_back(timer.time([&] { window.undo_action()->trigger(); }));
    redone.push_back(timer.time([&] { window.redo_action()->trigger(); }));
    window.undo_action()->trigger();
  }
  json out = {{"apply", step_json(applied)}, {"undo", step_json(undone)}, {"redo", step_json(redone)}};
  out["apply"]["phases"] = {{"operation_ms", median(operation)},
                            {"scene_ms", median(scene)},
                            {"view_ms", median(view)},
                            {"scene_process_cpu_ms", median(scene_cpu)},
                            {"view_process_cpu_ms", median(view_cpu)},
                            {"before_scene_minor_faults", median(before_faults)},
                            {"scene_minor_faults", median(scene_faults)},
                            {"view_minor_faults", median(view_faults)}};
  out["apply"]["runs"] = runs_json(applied, operation, scene, view);
  out["apply"]["prepare_updates_ms"] = median(idle);
  out["apply"]["undo_record_bytes"] = median(record);
  return out;
}

json run_size(std::size_t target, int ops, int cuts, int session, bool rebuilds, bool open_only,
              const std::string& only, const QString& dir) {
  deepcut::CactusOptions options;
  options.target_triangles = target;
  const QString path = dir + QString("/cactus_%1.glb").arg(target);
  std::size_t triangles = 0;
  {
    const deepcut::Model model = deepcut::make_cactus(options);
    for (const auto& mesh : model.meshes)
      for (const auto& prim : mesh.primitives) triangles += prim.mesh.face_count();
    deepcut::write_gltf(model, path.toStdString());
  }
  deepcut::studio::MainWindowOptions window_options;
  window_options.error_dialogs = false;  // an error ends the run, never waits on a dialog
  MainWindow window(window_options);
  window.resize(1280, 800);
  window.show();
  if (!QTest::qWaitForWindowExposed(&window)) throw std::runtime_error("the window is never exposed");
  Timer timer(window);
  const int frames_before = window.view()->frames_drawn();
  Timed open = timer.time([&] { window.open_file(path); });
  // The first frame's CPU time (open_file returns after the operations' posed model, which
  // draws no frame).
  if (window.view()->frames_drawn() != frames_before + 1)
    throw std::runtime_error("the open drew more than one frame");
  if (!window.scene()) throw std::runtime_error("could not open " + path.toStdString());
  // open_file returns once the operations' posed model is built too, after the first frame:
  // the frame is when the first frame ended.
  const MainWindow::OpenTiming parts = window.last_open_timing();
  const double ready = open.to_frame;
  open.to_frame = ms_since(open.start, parts.frame_end);
  json out = {{"triangles", triangles}, {"open", step_json({open})}};
  out["open"]["operations_ready_ms"] = ready;
  // Where the open's time went: the worker's marks (read and welded, posed, the view's data
  // built), its result delivered, the swap-in on the UI thread, the first frame.
  out["open"]["read_ms"] = parts.read_ms;
  out["open"]["posed_ms"] = parts.posed_ms;
  out["open"]["prepared_ms"] = parts.prepared_ms;
  out["open"]["delivered_ms"] = parts.delivered_ms;
  out["open"]["swap_in_ms"] = parts.swap_ms;
  out["open"]["first_frame_ms"] = parts.first_frame_ms;
  std::vector<Timed> unchanged;
  for (int i = 0; i < 3; ++i) unchanged.push_back(timer.time([&] { window.view()->render(); }));
  out["unchanged_render"] = step_json(unchanged);
  // The same frame multisampled (what View > Anti-aliasing > Multisampling costs here; the
  // studio's automatic choice turns it off on a software renderer).
  window.set_anti_aliasing(deepcut::studio::AntiAliasing::On, false);
  window.view()->render();  // the multisampled framebuffer is made on this frame: not timed
  std::vector<Timed> multisampled;
  for (int i = 0; i < 3; ++i) multisampled.push_back(timer.time([&] { window.view()->render(); }));
  out["unchanged_render_multisampled"] = step_json(multisampled);
  window.set_anti_aliasing(deepcut::studio::AntiAliasing::Automatic, false);
  if (open_only) return out;
  Placer place(window);
  if (session > 0) {
    out["session"] = run_session(window, place, session);
    return out;
  }
  // Memory first, on the model as opened: the cut steps below set aside what an undo or redo
  // brings back (the replaced primitive's scene data), and freeing that later would hide growth.
  const double before = resident_mib();
  for (int i = 0; i < ops; ++i) apply(window, place.drill());  // a miss changes nothing
  const double after = resident_mib();
  out["memory"] = {{"operations", ops},
                   {"resident_before_mib", before},
                   {"resident_after_mib", after},
                   {"growth_per_operation_kib", ops > 0 ? (after - before) * 1024.0 / ops : 0.0}};
  if (cuts > 0) {
    const double cuts_before = resident_mib();
    int made = 0;
    for (int i = 0; i < cuts; ++i)
      if (apply(window, i % 2 ? place.tip_cut() : place.cut())) {  // a miss changes nothing
        ++made;
        window.undo_action()->trigger();
      }
    const double cuts_after = resident_mib();
    out["cut_undo_memory"] = {
        {"cuts", made},
        {"resident_before_mib", cuts_before},
        {"resident_after_mib", cuts_after},
        {"growth_per_cut_kib", made > 0 ? (cuts_after - cuts_before) * 1024.0 / made : 0.0}};
  }
  for (const bool rebuild : {false, true}) {
    if (rebuild && !rebuilds) break;
    // The reference: the scene and its VTK data built again after every step.
    setenv("DEEPCUT_VIEW_REBUILD", rebuild ? "1" : "0", 1);
    const std::string suffix = rebuild ? "_rebuild" : "";
    if (only.empty() || only == "drill")
      out["drill" + suffix] = time_operation(window, timer, [&] { return place.drill(); });
    if (only.empty() || only == "tear")
      out["tear" + suffix] = time_operation(window, timer, [&] { return place.tear(); });
    if (only.empty() || only == "cut")
      out["cut" + suffix] = time_operation(window, timer, [&] { return place.cut(); });
  }
  setenv("DEEPCUT_VIEW_REBUILD", "0", 1);
  return out;
}

void print_session(const std::string& tri, const json& s) {
  const double mib = 1024.0 * 1024.0;
  for (const char* when : {"start", "after", "after_idle"}) {
    const json& m = s[when];
    std::printf(
        "%-10s session %s: %zu primitives, model %.1f MiB (capacity %.1f MiB), undo %.1f MiB, view %.1f MiB "
        "(used %.1f MiB), resident %.1f MiB, heap free %.1f MiB\n",
        tri.c_str(), when, m["primitives"].get<std::size_t>(), m["model_bytes"].get<double>() / mib,
        m["model_capacity_bytes"].get<double>() / mib, m["undo_bytes"].get<double>() / mib,
        m["view_bytes"].get<double>() / mib, m["view_used_bytes"].get<double>() / mib,
        m["resident_mib"].get<double>(), m["heap_free_mib"].get<double>());
  }
  std::printf(
      "%-10s session: %d operations (%d drills, %d tears, %d cuts, %d misses placed again); resident growth "
      "%.2fx the model opened (%.2fx once idle), resident %.2fx the start\n",
      tri.c_str(), s["operations"].get<int>(), s["drills"].get<int>(), s["tears"].get<int>(),
      s["cuts"].get<int>(), s["misses"].get<int>(), s["resident_growth_over_model"].get<double>(),
      s["idle_growth_over_model"].get<double>(), s["resident_after_over_start"].get<double>());
}

void print_table(const json& results) {
  std::printf("%-10s %-20s %14s %12s\n", "triangles", "step", "to render ms", "to frame ms");
  for (const json& r : results) {
    const std::string tri = std::to_string(r["triangles"].get<std::size_t>());
    auto row = [&](const std::string& name, const json& s) {
      std::printf("%-10s %-20s %14.1f %12.1f\n", tri.c_str(), name.c_str(), s["to_render_call_ms"].get<double>(),
                  s["to_frame_ms"].get<double>());
    };
    row("open", r["open"]);
    std::printf("%-10s open: read and welded %.1f ms, posed %.1f ms, view built %.1f ms, result delivered %.1f ms, "
                "swap-in %.1f ms, first frame %.1f ms (UI thread CPU %.1f ms); operations ready (posed model and "
                "grids) %.1f ms\n",
                tri.c_str(), r["open"]["read_ms"].get<double>(), r["open"]["posed_ms"].get<double>(),
                r["open"]["prepared_ms"].get<double>(), r["open"]["delivered_ms"].get<double>(),
                r["open"]["swap_in_ms"].get<double>(),
                r["open"]["first_frame_ms"].get<double>(), r["open"]["frame_ui_cpu_ms"].get<double>(),
                r["open"]["operations_ready_ms"].get<double>());
    row("render", r["unchanged_render"]);
    std::printf("%-10s render: UI thread CPU %.1f ms\n", tri.c_str(),
                r["unchanged_render"]["frame_ui_cpu_ms"].get<double>());
    row("render.multisampled", r["unchanged_render_multisampled"]);
    for (const char* kind : {"drill", "tear", "cut", "drill_rebuild", "tear_rebuild", "cut_rebuild"}) {
      if (!r.contains(kind)) continue;
      for (const char* step : {"apply", "undo", "redo"}) row(std::string(kind) + "." + step, r[kind][step]);
      const json& a = r[kind]["apply"];
      std::printf(
          "%-10s %s.apply to the render call: UI thread CPU %.1f ms, process CPU %.1f ms; operation %.1f ms",
          tri.c_str(), kind, a["to_render_call_ui_cpu_ms"].get<double>(),
          a["to_render_call_process_cpu_ms"].get<double>(), a["phases"]["operation_ms"].get<double>());
      if (std::strstr(kind, "_rebuild") == nullptr)  // (a rebuild is not timed by phase)
        std::printf(", scene %.1f ms, view %.1f ms", a["phases"]["scene_ms"].get<double>(),
                    a["phases"]["view_ms"].get<double>());
      std::printf("; minor faults %.0f (before the scene %.0f, scene %.0f, view %.0f)",
                  a["to_render_call_minor_faults"].get<double>(), a["phases"]["before_scene_minor_faults"].get<double>(),
                  a["phases"]["scene_minor_faults"].get<double>(), a["phases"]["view_minor_faults"].get<double>());
      std::printf("; undo record %.2f MiB; after the frame, prepare_updates %.1f ms\n",
                  a["undo_record_bytes"].get<double>() / (1024.0 * 1024.0), a["prepare_updates_ms"].get<double>());
      std::printf("%-10s %s.apply, each run to the render call:", tri.c_str(), kind);
      for (const json& run : a["runs"])
        std::printf(" %.1f ms (%ld minor faults)", run["to_render_call_ms"].get<double>(),
                    run["minor_faults"].get<long>());
      std::printf("\n");
    }
    if (r.contains("session")) print_session(tri, r["session"]);
    if (!r.contains("memory")) continue;
    const json& m = r["memory"];
    std::printf("%-10s memory: %.1f MiB resident, %.1f MiB after %d small drills (%.1f KiB per operation)\n",
                tri.c_str(), m["resident_before_mib"].get<double>(), m["resident_after_mib"].get<double>(),
                m["operations"].get<int>(), m["growth_per_operation_kib"].get<double>());
  }
}

}  // namespace

int main(int argc, char** argv) {
  deepcut::keep_freed_memory();  // an operation writes into the pages the last one freed
  bool as_json = false, quick = false, rebuilds = true, open_only = false;
  int ops = 100, cuts = 0, session = 0;
  std::size_t size = 0;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--json") == 0) {
      as_json = true;
    } else if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--no-rebuild") == 0) {
      rebuilds = false;
    } else if (std::strcmp(argv[i], "--open-only") == 0) {
      open_only = true;
    } else if (std::strcmp(argv[i], "--size") == 0 && i + 1 < argc) {
      size = static_cast<std::size_t>(std::max(1000L, std::atol(argv[++i])));
    } else if (std::strcmp(argv[i], "--ops") == 0 && i + 1 < argc) {
      ops = std::max(0, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--cuts") == 0 && i + 1 < argc) {
      cuts = std::max(0, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--session") == 0 && i + 1 < argc) {
      session = std::max(0, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc &&
               (std::strcmp(argv[i + 1], "drill") == 0 || std::strcmp(argv[i + 1], "tear") == 0 ||
                std::strcmp(argv[i + 1], "cut") == 0)) {
      only = argv[++i];
    } else {
      std::cerr << "deepcut_studio_bench: unknown argument '" << argv[i]
                << "' (--json, --quick, --size N, --no-rebuild, --ops N, --cuts N, --session N, --open-only, "
                   "--only "
                   "drill|tear|cut)\n";
      return 2;
    }
  }
  QApplication app(argc, argv);
  QTemporaryDir dir;
  try {
    json results = json::array();
    if (size > 0) {
      results.push_back(run_size(size, ops, cuts, session, rebuilds, open_only, only, dir.path()));
    } else {
      results.push_back(run_size(25300, ops, cuts, session, rebuilds, open_only, only, dir.path()));
      if (!quick)
        results.push_back(run_size(1000000, ops, cuts, session, rebuilds, open_only, only, dir.path()));
    }
    if (as_json)
      std::cout << results.dump(2) << "\n";
    else
      print_table(results);
  } catch (const std::exception& e) {
    std::cerr << "deepcut_studio_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
