// SPDX-License-Identifier: MIT
#pragma once
/// @file args.h
/// Argument parsing shared by the `deepcut` sub-commands: positionals, `-o OUT`, `--flag`,
/// `--key VALUE` and `--key=VALUE`. Usage errors throw UsageError (exit code 2). Each command
/// describes its arguments once, in a CommandSpec next to its code, and parses with it.

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"

namespace deepcut {
struct Model;
}

namespace deepcut::cli {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One option of a command: what its parser accepts and what its help says, in one row.
struct OptionSpec {
  std::string name;      ///< "--radius", "-o"
  std::string value;     ///< placeholder of its value ("R"); empty for a flag, which takes none
  std::string help;      ///< meaning and unit, one sentence or a few (the help wraps it)
  std::string fallback;  ///< the default as help shows it ("32"); empty when there is none
  bool required = false;
  /// Shown with the next option as alternatives: "[A | B]", or "(A | B)" when required.
  bool or_next = false;
};

/// A positional argument: its placeholder and meaning.
struct PositionalSpec {
  std::string name;  ///< "MODEL"
  std::string help;
};

/// A command as its parser reads it and `deepcut CMD --help` describes it (help.h renders it):
/// the parser accepts exactly the options listed, so help and parser cannot disagree.
struct CommandSpec {
  std::string name;                         ///< "cut"
  std::vector<PositionalSpec> positionals;  ///< in order
  std::string summary;                      ///< one line: what it does
  std::string details;                      ///< paragraphs ("\n\n" between them), unwrapped
  std::vector<OptionSpec> options;          ///< in synopsis order
  std::string example;                      ///< one command line, "deepcut ..."
  /// Usage after "deepcut ", lines joined by '\n' (continuations indented by four): filled in
  /// from the fields above by with_synopsis().
  std::string synopsis;
};

/// `spec` with its synopsis written from its name, positionals and options.
CommandSpec with_synopsis(CommandSpec spec);

/// A default as help shows it: `v` with up to six significant digits ("10", "0.7").
std::string number_text(double v);

/// Rows shared by several commands.
OptionSpec json_option(const std::string& what);  ///< --json, printing `what` on stdout
/// The options of every command that writes a model (-o OUT, required).
std::vector<OptionSpec> output_options();
/// --time and --animation: the pose the command's world-space arguments refer to.
std::vector<OptionSpec> pose_options();

class Args {
 public:
  /// @param flags   options without a value (e.g. "--json")
  /// @param options options with a value (e.g. "-o", "--radius")
  Args(const std::vector<std::string>& argv, const std::set<std::string>& flags, const std::set<std::string>& options);
  /// Accepts exactly the options of `spec` (a flag where OptionSpec::value is empty).
  Args(const std::vector<std::string>& argv, const CommandSpec& spec);

  const std::vector<std::string>& positionals() const { return positionals_; }
  bool flag(const std::string& name) const { return flags_.count(name) != 0; }
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  std::string value(const std::string& name, const std::string& fallback = "") const;
  /// Number option; UsageError when malformed or not finite.
  double number(const std::string& name, double fallback) const;
  /// Whole-number option (e.g. "3", "-1"; not "0.5" or "1e3x").
  /// @throws UsageError when the value is not an integer or does not fit in a long long.
  long long integer(const std::string& name, long long fallback) const;
  /// Comma-separated numbers, exactly `count` of them, all finite.
  std::vector<double> vector(const std::string& name, std::size_t count) const;

 private:
  std::vector<std::string> positionals_;
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
};

/// The option every writing command takes, `--compress none|draco|meshopt` (default none), as
/// the export options of its output. @throws UsageError for another value.
ExportOptions export_options(const Args& args);

/// "1 piece", "3 pieces": `n` followed by the noun in the right number.
std::string count_of(std::size_t n, const std::string& singular, const std::string& plural);

/// `--animation I` checked against a model with `count` animations: a whole number in
/// -1..count-1 (-1 is the rest pose). Default 0, or -1 when the model has no animation.
/// @throws UsageError for a non-integer or out-of-range index.
int animation_option(const Args& args, std::size_t count);

/// The animation an operation's `--time` refers to: `--animation I` (default 0), or -1 (rest
/// pose) when no `--time` is given. @throws UsageError for an index past the model's animations.
int pose_animation(const Args& args, const Model& model);

/// What the pose options cannot do on `model`, to report beside what reading it repaired (stderr
/// and `--json` problems): `--time` on a model without animation poses nothing, the rest pose is
/// used, and the user should read so rather than guess it from the result. Call it after the
/// options are checked (`pose_animation`), so a bad option is refused first.
std::vector<ImportProblem> pose_problems(const Args& args, const Model& model);

}  // namespace deepcut::cli
