// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/operation.h
/// One operation as a record (type, parameters, pose) and the one path that applies it. The
/// studio, `deepcut apply` and the `deepcut cut|tear|drill` commands all build an `Operation`
/// and call `apply_operation`, so they check the same rules and make the same model. Records
/// form the history that the studio undoes, redoes and re-runs, that `deepcut apply` replays,
/// and that exports carry in the root `extras` under "deepcut_history" (format: docs/cli.md,
/// "History files").

#include <map>
#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/ops/parameter_name.h"
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
  /// Morph weights set by hand per node (PoseKey::weights: the studio's morph weights panel),
  /// replacing what the animation gives those nodes; empty: the animation's. History files hold
  /// them as "weights": {"NODE": [w0, w1, ...]}.
  std::map<int, std::vector<float>> weights;
};

struct History {
  std::vector<Operation> operations;
};

/// What applying one operation did: the model operation's own result, typed (the alternative
/// matches the operation's kind: a cut gives a ModelCutResult, and so on).
struct OperationResult {
  OpStatus status = OpStatus::Ok;  ///< the model operation's status, repeated for convenience
  std::variant<ModelCutResult, ModelTearResult, ModelDrillResult> result;
};

/// "cut", "tear" or "drill": the operation's kind as history files name it.
const char* operation_name(const Operation& operation);

/// Parses a history file's text ({"operations": [...]}, format in docs/cli.md).
/// @throws Error{InvalidInput} naming the operation index and the problem.
History parse_history(const std::string& json_text);
/// The JSON text of a history (the inverse of parse_history).
std::string history_to_json(const History& history);

/// The checks of an operation's parameters that need no model, for front ends that refuse an
/// operation before they read one (`deepcut cut|tear|drill`): the operation's own checks
/// (check_cut_plane, the tear's blade checks, check_drill_arguments), which apply_operation
/// makes too, so the rules and messages are the same; `name` names the parameters in them (the
/// command line passes its flags, "--radius").
/// @throws Error{InvalidArgument} naming the operation ("drill: radius must be positive").
void check_operation(const Operation& operation, const ParameterName& name = {});

/// Applies one operation to the model and records it in the model's history when it changed
/// the model (status Ok).
/// @param posed  the model at a pose (posed_model.h), used and updated by drills and tears
///               (rebuilt when it was made for another pose or invalid); a cut reads it when it
///               was made for the operation's pose (else poses the model on its own and leaves it
///               as it was) and invalidates it when it changed the model.
/// @throws Error{InvalidArgument} for bad parameters (the operation's own checks), and for a
///         drill that removes every triangle of an instance while its
///         DrillOptions::refuse_swallowed_instances is set (the default; message "... use a
///         smaller radius"). Cuts and tears refuse before they change anything, but that drill
///         is refused once it has drilled: after an exception the model may be partly changed
///         and `posed` no longer describes it, so apply to a copy and invalidate `posed`.
OperationResult apply_operation(Model& model, const Operation& operation, PosedModel& posed);
/// Convenience: apply_operation with a posed model built for the call (the same result).
OperationResult apply_operation(Model& model, const Operation& operation);

/// The history recorded in the model's root extras (empty if none).
History model_history(const Model& model);
/// Appends `operation` to the history in the model's root extras, keeping other extras.
void record_operation(Model& model, const Operation& operation);

}  // namespace deepcut
