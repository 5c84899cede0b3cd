// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/history.h
/// Operations as records (type, parameters, pose), so the studio can undo, redo and re-run an
/// edited history, `deepcut apply` can replay one, and exports carry it in the root `extras`
/// under "deepcut_history" (format in README, "History files").

#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/ops/tear.h"

namespace deepcut {

struct CutOperation {
  Plane plane;
  CutOptions options;
};

struct DrillOperation {
  Cylinder cylinder;
  DrillOptions options;
};

/// A scalpel stroke: the blade's start and end poses (world space, in the operation's pose).
struct TearOperation {
  Blade start, end;
  TearOptions options;
};

/// One operation's parameters.
using OperationParams = std::variant<CutOperation, DrillOperation, TearOperation>;

struct Operation {
  OperationParams params;
  /// Animation whose pose the tool was placed against (-1: the rest pose). In history files an
  /// absent "animation" means 0, the model's first animation (the rest pose when it has none).
  int animation = -1;
  float time = 0.0f;  ///< seconds into that animation
};

struct History {
  std::vector<Operation> operations;
};

/// What applying one operation did, for reports (`summary_json` is a JSON object's text).
struct OperationReport {
  OpStatus status = OpStatus::Ok;
  std::string summary_json;
};

/// Parses a history file's text ({"operations": [...]}, see README).
/// @throws Error{InvalidInput} naming the operation index and the problem.
History parse_history(const std::string& json_text);
/// The JSON text of a history (the inverse of parse_history).
std::string history_to_json(const History& history);

/// Applies one operation to the model. @throws Error{InvalidArgument} for bad parameters.
/// @param index  optional preprocessing (posed_model.h) describing `model`: drills and tears use
///               and update it (see drill_model, tear_model), a cut invalidates it. After an
///               exception it no longer describes the model: invalidate it.
OperationReport apply_operation(Model& model, const Operation& operation, PosedModel* index = nullptr);

/// The history recorded in the model's root extras (empty if none).
History model_history(const Model& model);
/// Appends `operation` to the history in the model's root extras, keeping other extras.
void record_operation(Model& model, const Operation& operation);

}  // namespace deepcut
