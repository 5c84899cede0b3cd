// SPDX-License-Identifier: MIT
#pragma once
/// @file operation_report.h
/// The one report of an applied operation: `deepcut cut|tear|drill --json` print it (with their
/// timings) and `deepcut apply --json` prints it for each operation (with its "op"), so the
/// front ends report the same keys (listed in docs/cli.md). Core returns typed results
/// (OperationResult); turning them into JSON and sentences is the command line's business.

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "deepcut/core/ops/operation.h"

namespace deepcut::cli {

/// The report of `operation`, applied with `result`: "status", "problems" (`problems_report` of
/// what reading the model repaired or dropped, then `run_problems`: what the command's options
/// could not do on it) and, by kind,
///   cut:   "pieces" (per piece node: "node", "vertices", "triangles"), "intersection_points",
///          "rim_vertices";
///   tear:  "tear_vertices", "intersection_points", "slits", "width", "opening";
///   drill: "holes", "rim_vertices", "intersection_points", "triangles_removed",
///          "triangles_added", "wall_triangles", "unwalled_holes", and "wall_note" when a wall was
///          asked for and some holes got none.
/// @param model  the model after the operation (the cut's pieces are counted in it)
nlohmann::json operation_report(const Model& model, const Operation& operation, const OperationResult& result,
                                const std::vector<ImportProblem>& run_problems = {});

/// The "problems" key of every command's `--json` report: what reading the model repaired or
/// dropped, one object per kind: "kind" (a stable key), "message" (the line printed on stderr),
/// "count" and "places" (where it happened, as in the message). `deepcut info` adds the checks
/// of its meshes (`model_problems`).
nlohmann::json problems_report(const std::vector<ImportProblem>& problems);

/// One stderr line per kind of problem, naming the file: "deepcut: FILE: MESSAGE [KIND]". Every
/// command that reads a model prints them (`info` lists them in its report instead), so nothing
/// the reader repaired or dropped goes unsaid.
void print_problems(std::ostream& out, const std::string& file, const std::vector<ImportProblem>& problems);

/// What the operation did, for people: "cut into 2 pieces", "tore 1 slit, ...", "drilled 3 holes".
std::string operation_summary(const OperationResult& result);

/// The tool a miss names ("the blade misses the model"): "plane", "blade" or "drill".
const char* operation_tool(const Operation& operation);

}  // namespace deepcut::cli
