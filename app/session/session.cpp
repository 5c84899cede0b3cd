// SPDX-License-Identifier: MIT
#include "session.h"

#include <algorithm>
#include <chrono>
#include <new>
#include <optional>
#include <variant>

#include "deepcut/core/errors.h"

namespace deepcut::session {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Applies `entry` to `model` as `deepcut apply` would, noting whether it applied. An entry that
/// fails leaves `model` as it was, so a re-run goes on from what `deepcut apply` makes of the
/// entries that applied. `posed` (the posed model describing `model`, or nullptr) follows the
/// operation; after a failure it is invalidated, so the next operation rebuilds it.
void run_entry(Model& model, OperationEntry& entry, PosedModel* posed) {
  entry.error.clear();
  // A drill refuses to swallow an instance only once it has drilled (apply_operation): it runs on
  // a copy (O(model)), kept when it applies. Cuts and tears refuse before they change anything.
  std::optional<Model> copy;
  if (const auto* drill = std::get_if<DrillOperation>(&entry.operation.params);
      drill && drill->options.refuse_swallowed_instances)
    copy.emplace(model);
  Model& target = copy ? *copy : model;
  try {
    entry.status = (posed ? apply_operation(target, entry.operation, *posed) : apply_operation(target, entry.operation)).status;
    if (copy) model = std::move(*copy);
  } catch (const Error& e) {
    entry.status = OpStatus::Ok;
    entry.error = e.what();
    if (posed) posed->invalidate();
  } catch (const std::bad_alloc&) {
    if (posed) posed->invalidate();
    throw;  // the caller reports it
  } catch (const std::exception& e) {  // a defect in an operation: reported, never a crash
    entry.status = OpStatus::Ok;
    entry.error = std::string("internal error: ") + e.what();
    if (posed) posed->invalidate();
  }
}

}  // namespace

void Session::open(std::shared_ptr<const Model> model) {
  if (before_change_) before_change_();
  editing_ = {};
  steps_.clear();
  done_ = 0;
  reruns_.clear();
  original_ = model;
  current_ = std::move(model);
  opened_operations_ = current_ ? model_history(*current_).operations.size() : 0;
  posed_.reset();
  posed_state_.reset();
}

void Session::open(std::shared_ptr<const Model> model, std::unique_ptr<PosedModel> posed) {
  open(std::move(model));
  if (!posed || !current_) return;
  posed_ = std::move(posed);
  posed_state_ = current_;
}

void Session::push(std::shared_ptr<const Model> after) {
  editing_ = {};
  steps_.resize(done_);  // a new step drops the undone ones
  steps_.push_back({current_, after});
  done_ = steps_.size();
  current_ = std::move(after);
  // Forget the lists of states no step holds any more.
  reruns_.erase(std::remove_if(reruns_.begin(), reruns_.end(), [](const auto& r) { return r.first.expired(); }),
                reruns_.end());
}

void Session::commit(std::shared_ptr<const Model> state) {
  if (!current_ || !state) return;
  push(std::move(state));
}

void Session::undo() {
  if (!can_undo()) return;
  editing_ = {};
  current_ = steps_[--done_].before;
}

void Session::redo() {
  if (!can_redo()) return;
  editing_ = {};
  current_ = steps_[done_++].after;
}

Applied Session::apply(const Operation& op) {
  if (!current_) throw Error(ErrorCode::InvalidArgument, "apply: no model is open");
  const auto start = std::chrono::steady_clock::now();
  auto result = std::make_shared<Model>(*current_);
  // The operation follows and updates the posed model, which then describes `result` (a miss
  // leaves both as they were; a failure leaves it for a rebuild).
  PosedModel* posed = posed_for(current_);
  Applied applied;
  applied.result = apply_operation(*result, op, *posed);
  applied.ms = ms_since(start);
  if (applied.result.status != OpStatus::Ok) {
    posed_state_ = current_;
    return applied;
  }
  posed_state_ = result;
  // A state made by an edit keeps its skipped operations listed after a new one.
  if (const auto* entries = rerun_entries(current_.get())) {
    std::vector<OperationEntry> next = *entries;
    next.push_back({op, OpStatus::Ok, {}});
    reruns_.emplace_back(result, std::move(next));
  }
  push(std::move(result));
  return applied;
}

std::vector<Applied> Session::apply_history(const History& history, const std::string& source,
                                           const AppliedObserver& observer) {
  if (!current_) throw Error(ErrorCode::InvalidArgument, source + ": no model is open");
  std::vector<Applied> out;
  std::vector<std::shared_ptr<const Model>> states;  // after each operation that applied
  std::shared_ptr<Model> working;                    // Undo::None: the one copy every operation edits
  std::shared_ptr<const Model> state = current_;
  for (std::size_t i = 0; i < history.operations.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    std::shared_ptr<Model> next = working;
    if (!next) next = std::make_shared<Model>(*state);
    if (undo_mode_ == Undo::None) working = next;
    PosedModel* posed = posed_for(state);
    Applied applied;
    try {
      applied.result = apply_operation(*next, history.operations[i], *posed);
    } catch (const Error& e) {
      throw Error(e.code(), source + ": operation " + std::to_string(i) + ": " + e.what());
    }
    applied.ms = ms_since(start);
    if (observer) observer(i, *next, applied);
    out.push_back(std::move(applied));
    if (out.back().result.status != OpStatus::Ok) {
      posed_state_ = state;
      continue;
    }
    posed_state_ = next;
    state = next;
    if (undo_mode_ == Undo::PerOperation) states.push_back(state);
  }
  if (undo_mode_ == Undo::None && state != current_) states.push_back(state);
  for (auto& after : states) push(std::move(after));
  return out;
}

const std::vector<OperationEntry>* Session::rerun_entries(const Model* model) const {
  for (const auto& [state, entries] : reruns_)
    if (const auto alive = state.lock(); alive && alive.get() == model) return &entries;
  return nullptr;
}

std::vector<OperationEntry> Session::operations() const {
  if (editing_.index >= 0) return editing_.entries;
  if (!current_) return {};
  if (const auto* entries = rerun_entries(current_.get())) return *entries;
  std::vector<OperationEntry> out;
  const History history = model_history(*current_);
  for (std::size_t i = opened_operations_; i < history.operations.size(); ++i)
    out.push_back({history.operations[i], OpStatus::Ok, {}});
  return out;
}

bool Session::begin_edit(int index) {
  if (editing_.index >= 0) cancel_edit();
  const std::vector<OperationEntry> entries = operations();
  if (!current_ || !original_ || index < 0 || index >= static_cast<int>(entries.size())) return false;
  // The state before the operation: the opened model and the operations before it, re-run.
  auto base = std::make_shared<Model>(*original_);
  std::vector<OperationEntry> replayed = entries;
  PosedModel* posed = index < 1 ? nullptr : posed_for(original_);
  for (int i = 0; i < index; ++i) run_entry(*base, replayed[static_cast<std::size_t>(i)], posed);
  if (posed) posed_state_ = std::shared_ptr<const Model>(base);
  editing_ = {index, current_, entries};
  current_ = std::move(base);
  return true;
}

void Session::cancel_edit() {
  if (editing_.index < 0) return;
  current_ = editing_.current;
  editing_ = {};
}

EditOutcome Session::finish_edit(const Operation& op) { return commit_edit(prepare_edit(op)); }

EditRun Session::prepare_edit(const Operation& op, const RerunObserver& observer) const {
  const auto start = std::chrono::steady_clock::now();
  const auto index = static_cast<std::size_t>(editing_.index);
  EditRun run;
  run.entries = editing_.entries;
  run.entries[index].operation = op;
  auto result = std::make_shared<Model>(*current_);  // the state before the edited operation
  run.posed = std::make_unique<PosedModel>();       // the first operation builds it at its pose
  if (observer) observer(index, run.entries.size());
  run_entry(*result, run.entries[index], run.posed.get());
  run.outcome.edited = run.entries[index];
  if (run.outcome.edited.applied()) {
    for (std::size_t i = index + 1; i < run.entries.size(); ++i) {
      if (observer) observer(i, run.entries.size());
      run_entry(*result, run.entries[i], run.posed.get());
      if (!run.entries[i].applied()) ++run.outcome.skipped;
    }
    run.result = std::move(result);
  }
  run.outcome.ms = ms_since(start);
  return run;
}

EditOutcome Session::commit_edit(EditRun run) {
  if (!run.result) return run.outcome;  // the edit goes on
  if (before_change_) before_change_();
  posed_ = std::move(run.posed);
  posed_state_ = run.result;
  reruns_.emplace_back(run.result, std::move(run.entries));
  current_ = editing_.current;
  push(run.result);  // ends the edit
  return run.outcome;
}

const PosedModel* Session::posed_model() const {
  if (!posed_ || !current_ || posed_state_.lock() != current_ || !posed_->valid()) return nullptr;
  return posed_.get();
}

bool Session::refresh_posed_model(int animation, float time) {
  return refresh_posed_model(PoseKey(animation, time));
}

bool Session::refresh_posed_model(const PoseKey& key) {
  if (!current_) return false;
  try {
    posed_for(current_)->prepare(*current_, key);
    posed_state_ = current_;
    return true;
  } catch (const Error&) {
    posed_state_.reset();  // the next operation builds it (and reports what is wrong)
  } catch (const std::bad_alloc&) {
    posed_.reset();
    posed_state_.reset();
  }
  return false;
}

PosedModel* Session::posed_for(const std::shared_ptr<const Model>& state) {
  if (before_change_) before_change_();
  if (!posed_) posed_ = std::make_unique<PosedModel>();
  if (posed_state_.lock() != state) posed_->invalidate();  // the next operation builds it at its pose
  posed_state_.reset();  // it may change: it describes no state until the caller says so
  return posed_.get();
}

}  // namespace deepcut::session
