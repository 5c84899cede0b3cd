// SPDX-License-Identifier: MIT
// The golden corpus: several hundred seeded `deepcut` command lines (cut, tear, drill, apply;
// posed and rest pose; over every asset model; a few that miss and a few malformed ones) run
// through the CLI, each reduced to its exit code and hashes of what it produced. The recorded
// results (tests/golden/corpus.txt) pin the CLI's behaviour byte for byte: any change to an
// output file, a report or an error message shows up here with the command that replays it.
//
// corpus.txt: '#' lines are comments; every other line is one operation, tab-separated:
//   ID  exit=N  file=H  json=H  err=H  cmd=deepcut ...  [history=JSON]
// H is a 64-bit FNV-1a hash in hex ("none" when there is no such output): `file` of the bytes of
// the output file (out/ID.glb), `json` of the --json report on stdout with every timing key
// (`ms` and any key ending in `_ms`) removed, re-serialised with sorted keys, `err` of stderr.
// The commands run in a scratch directory holding a link `assets` to the repository's assets/,
// `out/` for the outputs and `hist/` for the history files of `apply` (written from `history`).
// The glb files hold no timings or timestamps (the reports' timing keys are the only variable
// part of the CLI's output), so nothing else is normalised.
//
// Environment:
//   DEEPCUT_GOLDEN_RECORD=1  generate the operations anew (golden_corpus.h, fixed seeds), run them
//                            twice (the two runs must agree) and rewrite tests/golden/corpus.txt
//                            in the source tree, instead of comparing.
//   DEEPCUT_GOLDEN_CLI=PATH  run this deepcut binary instead of the one built with the tests
//                            (to check another build against the recorded corpus).
//   DEEPCUT_GOLDEN_JOBS=N    operations run in parallel (default 2).
//
// Without the static formats plugin (a build without VTK) the CLI cannot read .obj: the
// operations on assets/models/spot/spot.obj are skipped then.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fixtures.h"
#include "golden_corpus.h"
#include "tools.h"

namespace deepcut::golden {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kCorpusPath = std::string(DEEPCUT_SOURCE_DIR) + "/tests/golden/corpus.txt";

std::string hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string read_file(const std::string& path, bool& exists) {
  std::ifstream in(path, std::ios::binary);
  exists = static_cast<bool>(in);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool is_timing_key(const std::string& key) {
  return key == "ms" || (key.size() > 3 && key.compare(key.size() - 3, 3, "_ms") == 0);
}

void strip_timings(json& j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) it = is_timing_key(it.key()) ? j.erase(it) : std::next(it);
    for (auto& v : j) strip_timings(v);
  } else if (j.is_array()) {
    for (auto& v : j) strip_timings(v);
  }
}

// What one operation produced.
struct Result {
  int exit_code = -1;
  std::string file, json, err;  ///< hashes in hex, or "none"
  std::vector<std::string> statuses;  ///< "status" of each operation in the report
};

std::string line_of(const CorpusOp& op, const Result& r) {
  std::string line = op.id + "\texit=" + std::to_string(r.exit_code) + "\tfile=" + r.file + "\tjson=" + r.json +
                     "\terr=" + r.err + "\tcmd=" + op.command;
  if (!op.history.empty()) line += "\thistory=" + op.history;
  return line;
}

std::string cli_path() {
  const char* env = std::getenv("DEEPCUT_GOLDEN_CLI");
  return env && *env ? std::string(env) : std::string(DEEPCUT_CLI);
}

// A scratch directory with assets/, out/ and hist/.
std::string make_run_dir() {
  const std::string dir = test::temp_dir("golden");
  fs::create_directory_symlink(DEEPCUT_ASSETS_DIR, dir + "/assets");
  fs::create_directories(dir + "/out");
  fs::create_directories(dir + "/hist");
  return dir;
}

std::string replay_command(const CorpusOp& op) {
  std::string s = "cd \"$(mktemp -d)\" && ln -s " + test::quote(DEEPCUT_ASSETS_DIR) + " assets && mkdir out hist && ";
  if (!op.history.empty()) s += "printf '%s' " + test::quote(op.history) + " > hist/" + op.id + ".json && ";
  return s + test::quote(cli_path()) + op.command.substr(std::string("deepcut").size());
}

Result run_op(const std::string& dir, const CorpusOp& op) {
  if (!op.history.empty()) std::ofstream(dir + "/hist/" + op.id + ".json", std::ios::binary) << op.history;
  const std::string args = op.command.substr(std::string("deepcut").size());
  const test::RunResult run = test::run_command("cd " + test::quote(dir) + " && " + test::quote(cli_path()) + args);
  Result r;
  r.exit_code = run.exit_code;
  bool exists = false;
  const std::string bytes = read_file(dir + "/out/" + op.id + ".glb", exists);
  r.file = exists ? hex(fnv1a(bytes)) : "none";
  r.err = run.err.empty() ? "none" : hex(fnv1a(run.err));
  if (run.out.empty()) {
    r.json = "none";
  } else {
    json report = json::parse(run.out, nullptr, false);
    if (report.is_discarded()) {
      r.json = "raw:" + hex(fnv1a(run.out));
    } else {
      if (report.contains("status")) r.statuses.push_back(report["status"].get<std::string>());
      if (report.contains("operations"))
        for (const auto& o : report["operations"]) r.statuses.push_back(o.value("status", "?"));
      strip_timings(report);
      r.json = hex(fnv1a(report.dump()));
    }
  }
  return r;
}

std::vector<Result> run_all(const std::vector<CorpusOp>& ops) {
  const std::string dir = make_run_dir();
  std::vector<Result> results(ops.size());
  std::atomic<std::size_t> next{0};
  const char* jobs_env = std::getenv("DEEPCUT_GOLDEN_JOBS");
  const int jobs = std::max(1, jobs_env ? std::atoi(jobs_env) : 2);
  std::vector<std::thread> workers;
  for (int w = 0; w < jobs; ++w)
    workers.emplace_back([&] {
      for (std::size_t i; (i = next++) < ops.size();) results[i] = run_op(dir, ops[i]);
    });
  for (auto& w : workers) w.join();
  fs::remove_all(dir);
  return results;
}

bool readable(const CorpusOp& op) { return DEEPCUT_HAVE_STATIC_FORMATS || op.command.find(".obj") == std::string::npos; }

// The corpus file's operations and their recorded lines.
std::vector<std::pair<CorpusOp, std::string>> read_corpus() {
  std::ifstream in(kCorpusPath);
  std::vector<std::pair<CorpusOp, std::string>> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    CorpusOp op;
    std::stringstream fields(line);
    std::getline(fields, op.id, '\t');
    for (std::string f; std::getline(fields, f, '\t');) {
      if (f.rfind("cmd=", 0) == 0) op.command = f.substr(4);
      if (f.rfind("history=", 0) == 0) op.history = f.substr(8);
    }
    out.emplace_back(op, line);
  }
  return out;
}

std::string command_name(const CorpusOp& op) {
  const auto a = op.command.find(' ') + 1;
  return op.command.substr(a, op.command.find(' ', a) - a);
}

// Operations per command and per asset, and how many changed the model, missed or failed.
void print_summary(const std::vector<CorpusOp>& ops, const std::vector<Result>& results) {
  std::map<std::string, int> per_command, per_asset;
  int changed = 0, missed = 0, failed = 0;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    ++per_command[command_name(ops[i])];
    const auto a = ops[i].command.find("assets/");
    ++per_asset[ops[i].id.rfind("bad-", 0) == 0 ? "(malformed)" : ops[i].command.substr(a, ops[i].command.find(' ', a) - a)];
    const auto& st = results[i].statuses;
    if (results[i].exit_code != 0) ++failed;
    else if (std::any_of(st.begin(), st.end(), [](const std::string& s) { return s == "ok"; })) ++changed;
    else ++missed;
  }
  std::cout << "golden corpus: " << ops.size() << " operations: " << changed << " changed the model, " << missed
            << " missed, " << failed << " failed (exit != 0)\n";
  for (const auto& [k, n] : per_command) std::cout << "  " << k << ": " << n << "\n";
  for (const auto& [k, n] : per_asset) std::cout << "  " << k << ": " << n << "\n";
}

void record() {
  const std::vector<CorpusOp> ops = generate_corpus(DEEPCUT_ASSETS_DIR);
  ASSERT_TRUE(DEEPCUT_HAVE_STATIC_FORMATS) << "recording needs the static formats plugin (spot.obj)";
  const std::vector<Result> first = run_all(ops), second = run_all(ops);
  std::ostringstream text;
  text << "# Golden corpus of the deepcut CLI: see tests/golden/golden_corpus_test.cpp (format, how to re-record).\n";
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const std::string a = line_of(ops[i], first[i]), b = line_of(ops[i], second[i]);
    ASSERT_EQ(a, b) << "two runs disagree: " << ops[i].id << "\n  replay: " << replay_command(ops[i]);
    text << a << "\n";
  }
  std::ofstream(kCorpusPath, std::ios::binary) << text.str();
  print_summary(ops, first);
  std::cout << "recorded " << ops.size() << " operations in " << kCorpusPath << "\n";
}

std::string differing(const std::string& recorded, const std::string& now) {
  std::string out;
  std::stringstream a(recorded), b(now);
  for (std::string fa, fb; std::getline(a, fa, '\t') && std::getline(b, fb, '\t');)
    if (fa != fb) out += "\n    recorded " + fa.substr(0, 120) + "\n    now      " + fb.substr(0, 120);
  return out;
}

TEST(GoldenCorpus, every_operation_gives_the_recorded_exit_code_output_and_report) {
  const char* rec = std::getenv("DEEPCUT_GOLDEN_RECORD");
  if (rec && std::string(rec) == "1") return record();

  // Every model under assets/ is in the corpus (a new one means recording it anew).
  const auto assets = corpus_assets();
  auto models = test::asset_models();
  models.push_back(test::static_models().front());
  for (const auto& m : models) {
    const std::string rel = "assets/" + fs::relative(m, DEEPCUT_ASSETS_DIR).generic_string();
    EXPECT_NE(std::find(assets.begin(), assets.end(), rel), assets.end()) << rel << " is not in the golden corpus";
  }

  std::vector<CorpusOp> ops;
  std::vector<std::string> recorded;
  int skipped = 0;
  for (auto& [op, line] : read_corpus()) {
    if (!readable(op)) {
      ++skipped;
      continue;
    }
    ops.push_back(op);
    recorded.push_back(line);
  }
  ASSERT_GE(ops.size(), 300u) << kCorpusPath << " is missing or short";
  const std::vector<Result> results = run_all(ops);
  print_summary(ops, results);
  if (skipped) std::cout << "skipped " << skipped << " operations on .obj models (no static formats plugin)\n";
  int mismatches = 0;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const std::string now = line_of(ops[i], results[i]);
    if (now == recorded[i]) continue;
    if (++mismatches > 25) continue;
    ADD_FAILURE() << ops[i].id << " differs:" << differing(recorded[i], now) << "\n  replay: " << replay_command(ops[i]);
  }
  EXPECT_EQ(mismatches, 0) << "operations differ from " << kCorpusPath
                           << " (if the change is intended, re-record with DEEPCUT_GOLDEN_RECORD=1)";
}

}  // namespace
}  // namespace deepcut::golden
