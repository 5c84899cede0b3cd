// SPDX-License-Identifier: MIT
#include "session.h"

#include <algorithm>
#include <chrono>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "deepcut/core/errors.h"
#include "deepcut/core/model_undo.h"

namespace deepcut::session {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Applies `entry` to `model` as `deepcut apply` would, noting whether it applied. An entry that
/// fails leaves `model` as it was (its edits are recorded and taken back), so a re-run goes on
/// from what `deepcut apply` makes of the entries that applied. `posed` (the posed model
/// describing `model`, or nullptr) follows the operation; after a failure it is invalidated, so
/// the next operation rebuilds it.
void run_entry(Model& model, OperationEntry& entry, PosedModel* posed) {
  entry.error.clear();
  // A drill refuses to swallow an instance only once it has drilled (apply_operation): what it
  // did is taken back from the record. Cuts and tears refuse before they change anything.
  ModelRecorder recorder(model);
  auto fail = [&](std::string message) {
    recorder.finish().undo(model);
    entry.status = OpStatus::Ok;
    entry.error = std::move(message);
    if (posed) posed->invalidate();
  };
  try {
    entry.status = (posed ? apply_operation(model, entry.operation, *posed) : apply_operation(model, entry.operation)).status;
    recorder.finish();
  } catch (const Error& e) {
    fail(e.what());
  } catch (const std::bad_alloc&) {
    if (posed) posed->invalidate();
    throw;  // the caller reports it
  } catch (const std::exception& e) {  // a defect in an operation: reported, never a crash
    fail(std::string("internal error: ") + e.what());
  }
}

/// The model behind `model`: taken over when the caller handed the only reference (nobody else
/// sees it change), else a copy.
std::shared_ptr<Model> own(std::shared_ptr<const Model> model) {
  if (model.use_count() == 1) return std::const_pointer_cast<Model>(std::move(model));
  return std::make_shared<Model>(*model);
}

ModelChange structure() {
  ModelChange change;
  change.structure = true;
  return change;
}

/// The step's change, with the origins of the pieces a cut made (ModelChange::origins): the
/// followers copy what they drew of the cut instances for everything but the rim.
ModelChange with_origins(ModelChange change, const OperationResult& result) {
  if (const auto* cut = std::get_if<ModelCutResult>(&result.result); cut && change.structure && change.mapped)
    change.origins = cut->origins;
  return change;
}

// Runs `f` when the scope is left, however it is left (a return, a miss, an exception).
template <class F>
struct AtExit {
  F f;
  ~AtExit() { f(); }
};
template <class F>
AtExit<F> at_exit(F f) {
  return {std::move(f)};
}

}  // namespace

void Session::open(std::shared_ptr<const Model> model, bool take_over) {
  changing();
  editing_ = {};
  steps_.clear();
  done_ = 0;
  lent_ = false;
  if (take_over) {
    live_ = std::const_pointer_cast<Model>(std::move(model));
  } else {
    live_ = model ? own(std::move(model)) : nullptr;
  }
  current_ = live_;
  opened_operations_ = live_ ? model_history(*live_).operations.size() : 0;
  posed_.reset();
  posed_state_ = nullptr;
  stash_.clear();
}

void Session::open(std::shared_ptr<const Model> model, std::unique_ptr<PosedModel> posed) {
  open(std::move(model), /*take_over=*/true);
  if (!posed || !live_) return;
  posed_ = std::move(posed);
  posed_state_ = live_.get();
}

void Session::push(ModelStep record, std::optional<std::vector<OperationEntry>> entries) {
  ++version_;
  steps_.resize(done_);  // a new step drops the undone ones
  lent_ = false;
  if (!record.exact()) steps_.clear();  // it cannot be taken back: nothing before it can either
  steps_.push_back({std::move(record), std::move(entries)});
  done_ = steps_.size();
}

const ModelStep* Session::last_structural(const std::vector<ModelStep>& pending) const {
  for (std::size_t i = pending.size(); i-- > 0;)
    if (pending[i].change().structure) return &pending[i];
  for (std::size_t i = done_; i-- > 0;)
    if (steps_[i].record.change().structure) return &steps_[i].record;
  return nullptr;
}

void Session::lend_undone(ModelRecorder& recorder) {
  if (!can_redo()) return;
  recorder.lend_spares([this] {
    lent_ = true;
    std::vector<SurfaceMesh> out;
    for (std::size_t i = done_; i < steps_.size(); ++i)
      for (SurfaceMesh& mesh : steps_[i].record.take_meshes()) out.push_back(std::move(mesh));
    return out;
  });
}

void Session::drop_lent() {
  if (!lent_) return;
  lent_ = false;
  steps_.resize(done_);
  stash_.clear();  // it kept contents of the steps dropped
}

ModelChange Session::commit(std::shared_ptr<const Model> state) {
  if (!live_ || !state) return {};
  cancel_edit();
  changing();
  std::shared_ptr<Model> owned = own(std::move(state));
  push(ModelStep::replace(*live_, std::move(*owned)), std::nullopt);
  posed_state_ = nullptr;
  stash_.clear();
  return structure();
}

ModelChange Session::undo() {
  if (!can_undo()) return {};
  const bool was_editing = editing_.index >= 0;
  cancel_edit();
  changing();
  ModelChange change = steps_[--done_].record.undo(*live_);
  follow(change);
  return was_editing ? structure() : change;
}

ModelChange Session::redo() {
  if (!can_redo()) return {};
  const bool was_editing = editing_.index >= 0;
  cancel_edit();
  changing();
  ModelChange change = steps_[done_++].record.redo(*live_);
  follow(change);
  return was_editing ? structure() : change;
}

namespace {
template <typename Steps>
std::size_t bytes_of(const Steps& steps, std::size_t count) {
  std::size_t out = 0;
  for (std::size_t i = 0; i < count; ++i) {
    out += sizeof(steps[i]) + steps[i].record.bytes();
    if (steps[i].entries) out += steps[i].entries->capacity() * sizeof(OperationEntry);
  }
  return out;
}
}  // namespace

std::size_t Session::undo_bytes() const { return bytes_of(steps_, steps_.size()); }

std::size_t Session::done_bytes() const { return bytes_of(steps_, done_); }

void Session::follow(const ModelChange& change) {
  if (!posed_ || posed_state_ != live_.get() || !posed_->valid()) {
    stash_.clear();
    return;
  }
  if (change.structure) {
    follow_structure(change);
  } else if (!change.empty()) {
    posed_->follow(*live_, change);
  }
}

void Session::follow_structure(const ModelChange& change) {
  bool stashed = change.mapped && stash_key_ == posed_->key();
  for (const PrimitiveContent& a : change.arrived)
    for (std::size_t n = 0; n < live_->nodes.size() && stashed; ++n)
      if (live_->nodes[n].mesh == a.mesh && !stash_.count({a.tag, static_cast<int>(n)})) stashed = false;
  if (stashed) {
    posed_->follow(*live_, change, PoseDetail::Full, &stash_);  // O(nodes): nothing is built
    stash_key_ = posed_->key();
    return;
  }
  // The instances of what left are kept for the undo or redo that brings it back; the posed
  // model (describing the state before the step) is rebuilt when asked for.
  PoseStash left;
  if (change.mapped)
    for (const PrimitiveContent& l : change.left)
      for (const auto& [key, inst] : posed_->instances())
        if (inst.mesh == l.mesh && inst.primitive == l.primitive && !inst.posed.empty())
          left[{l.tag, key.first}] = std::move(*posed_->find(key.first, key.second));
  stash_ = std::move(left);
  stash_key_ = posed_->key();
  posed_->invalidate();
  posed_state_ = nullptr;
}

Applied Session::apply(const Operation& op) {
  if (!live_) throw Error(ErrorCode::InvalidArgument, "apply: no model is open");
  cancel_edit();
  const auto start = std::chrono::steady_clock::now();
  // The operation follows and updates the posed model, which then describes the live model
  // again (a miss leaves both as they were; a failure leaves it for a rebuild).
  PosedModel* posed = posed_for(live_.get());
  Applied applied;
  ModelRecorder recorder(*live_);
  const auto dropping = at_exit([this] { drop_lent(); });  // however it ends, unless a step is pushed
  lend_undone(recorder);
  try {
    applied.result = apply_operation(*live_, op, *posed);
  } catch (...) {
    recorder.finish().undo(*live_);  // what a refused drill did is taken back
    throw;
  }
  ModelStep record = recorder.finish(last_structural({}));
  if (applied.result.status != OpStatus::Ok) {
    if (!record.change().empty()) record.undo(*live_);  // a miss changes nothing
    posed_state_ = live_.get();
    applied.ms = ms_since(start);
    return applied;
  }
  posed_state_ = live_.get();
  stash_.clear();  // the steps undone, whose contents it kept, are dropped
  applied.change = with_origins(record.change(), applied.result);
  // A state made by an edit keeps its skipped operations listed after a new one.
  std::optional<std::vector<OperationEntry>> entries;
  if (const auto* listed = rerun_entries()) {
    entries = *listed;
    entries->push_back({op, OpStatus::Ok, {}});
  }
  push(std::move(record), std::move(entries));
  applied.ms = ms_since(start);
  return applied;
}

std::vector<Applied> Session::apply_history(const History& history, const std::string& source,
                                           const AppliedObserver& observer) {
  if (!live_) throw Error(ErrorCode::InvalidArgument, source + ": no model is open");
  cancel_edit();
  std::vector<Applied> out;
  std::vector<ModelStep> records;  // one per operation that applied (Undo::None: one in all)
  std::optional<ModelRecorder> recorder;
  const auto dropping = at_exit([this] { drop_lent(); });  // however it ends, unless a step is pushed
  auto take_back = [&] {  // a bad operation leaves the session as it was
    if (recorder) recorder->finish().undo(*live_);
    for (std::size_t i = records.size(); i-- > 0;) records[i].undo(*live_);
    posed_state_ = nullptr;
  };
  auto record_next = [&] {
    recorder.emplace(*live_);
    lend_undone(*recorder);
  };
  if (undo_mode_ == Undo::None) record_next();
  for (std::size_t i = 0; i < history.operations.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    PosedModel* posed = posed_for(live_.get());
    if (undo_mode_ == Undo::PerOperation) record_next();
    Applied applied;
    try {
      applied.result = apply_operation(*live_, history.operations[i], *posed);
    } catch (const Error& e) {
      take_back();
      throw Error(e.code(), source + ": operation " + std::to_string(i) + ": " + e.what());
    } catch (...) {
      take_back();
      throw;
    }
    posed_state_ = live_.get();
    if (undo_mode_ == Undo::PerOperation) {
      ModelStep record = recorder->finish(last_structural(records));
      recorder.reset();
      if (applied.result.status == OpStatus::Ok) {
        applied.change = with_origins(record.change(), applied.result);
        records.push_back(std::move(record));
      }
    }
    applied.ms = ms_since(start);
    try {
      if (observer) observer(i, *live_, applied);
    } catch (...) {  // the observer's failure is the history's: nothing changes
      take_back();
      throw;
    }
    out.push_back(std::move(applied));
  }
  if (recorder) {
    ModelStep record = recorder->finish(last_structural(records));
    if (!record.change().empty()) records.push_back(std::move(record));
  }
  if (!records.empty()) stash_.clear();
  for (auto& record : records) push(std::move(record), std::nullopt);
  return out;
}

const std::vector<OperationEntry>* Session::rerun_entries() const {
  if (done_ == 0 || !steps_[done_ - 1].entries) return nullptr;
  return &*steps_[done_ - 1].entries;
}

std::vector<OperationEntry> Session::operations() const {
  if (editing_.index >= 0) return editing_.entries;
  if (!live_) return {};
  if (const auto* entries = rerun_entries()) return *entries;
  std::vector<OperationEntry> out;
  const History history = model_history(*live_);
  for (std::size_t i = opened_operations_; i < history.operations.size(); ++i)
    out.push_back({history.operations[i], OpStatus::Ok, {}});
  return out;
}

Model Session::opened_copy() {
  const std::size_t done = done_;
  changing();
  for (std::size_t i = done; i-- > 0;) steps_[i].record.undo(*live_);
  Model out = *live_;
  for (std::size_t i = 0; i < done; ++i) steps_[i].record.redo(*live_);
  return out;
}

bool Session::begin_edit(int index) {
  if (editing_.index >= 0) cancel_edit();
  const std::vector<OperationEntry> entries = operations();
  if (!live_ || index < 0 || index >= static_cast<int>(entries.size())) return false;
  // The state before the operation: the opened model and the operations before it, re-run.
  auto base = std::make_shared<Model>(opened_copy());
  std::vector<OperationEntry> replayed = entries;
  PosedModel* posed = index < 1 ? nullptr : posed_for(nullptr);
  for (int i = 0; i < index; ++i) run_entry(*base, replayed[static_cast<std::size_t>(i)], posed);
  if (posed) posed_state_ = base.get();
  editing_ = {index, base, entries};
  current_ = std::move(base);
  return true;
}

void Session::cancel_edit() {
  if (editing_.index < 0) return;
  changing();
  if (posed_state_ == editing_.base.get()) posed_state_ = nullptr;
  current_ = live_;
  editing_ = {};
}

EditOutcome Session::finish_edit(const Operation& op) { return commit_edit(prepare_edit(op)); }

EditRun Session::prepare_edit(const Operation& op, const RerunObserver& observer) const {
  const auto start = std::chrono::steady_clock::now();
  const auto index = static_cast<std::size_t>(editing_.index);
  EditRun run;
  run.entries = editing_.entries;
  run.entries[index].operation = op;
  // The edit's base is only read (the studio shows it meanwhile, and Cancel keeps the edit as
  // it was): the re-run edits a copy of it, with a posed model of its own (the first operation
  // builds it at its pose), and commit_edit moves the result into the live model.
  auto result = std::make_shared<Model>(*editing_.base);
  run.posed = std::make_unique<PosedModel>();
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
    run.outcome.change = structure();
  }
  run.outcome.ms = ms_since(start);
  return run;
}

EditOutcome Session::commit_edit(EditRun run) {
  if (!run.result) return run.outcome;  // the edit goes on
  cancel_edit();
  changing();
  // One step: the re-run replaces the model (the step holds the state it replaced, by move).
  push(ModelStep::replace(*live_, std::move(*run.result)), std::move(run.entries));
  posed_ = std::move(run.posed);  // it described the result, now moved into the live model
  stash_.clear();
  posed_state_ = posed_ ? live_.get() : nullptr;
  return run.outcome;
}

const PosedModel* Session::posed_model() const {
  if (!posed_ || !current_ || posed_state_ != current_.get() || !posed_->valid()) return nullptr;
  return posed_.get();
}

bool Session::refresh_posed_model(int animation, float time) {
  return refresh_posed_model(PoseKey(animation, time));
}

bool Session::refresh_posed_model(const PoseKey& key) {
  if (!current_) return false;
  if (key != stash_key_) stash_.clear();  // posed at another pose
  try {
    posed_for(current_.get())->prepare(*current_, key);
    posed_state_ = current_.get();
    return true;
  } catch (const Error&) {
    posed_state_ = nullptr;  // the next operation builds it (and reports what is wrong)
  } catch (const std::bad_alloc&) {
    posed_.reset();
    posed_state_ = nullptr;
  }
  return false;
}

bool Session::adopt_posed_model(std::unique_ptr<PosedModel> posed, const Model* built_for,
                                std::uint64_t version) {
  if (!posed || !posed->valid() || !live_ || built_for != live_.get() || current_ != live_ || version != version_ ||
      editing_.index >= 0)
    return false;
  if (before_change_) before_change_();
  if (posed->key() != stash_key_) stash_.clear();  // posed at another pose
  posed_ = std::move(posed);
  posed_state_ = live_.get();
  return true;
}

void Session::changing() {
  ++version_;
  if (before_change_) before_change_();
}

PosedModel* Session::posed_for(const Model* state) {
  changing();
  if (!posed_) posed_ = std::make_unique<PosedModel>();
  if (posed_state_ != state || !state) posed_->invalidate();  // the next operation builds it at its pose
  posed_state_ = nullptr;  // it may change: it describes no state until the caller says so
  return posed_.get();
}

}  // namespace deepcut::session
