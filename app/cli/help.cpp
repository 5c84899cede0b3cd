// SPDX-License-Identifier: MIT
#include "help.h"

#include <algorithm>

#include "commands.h"
#include "operation_command.h"

namespace deepcut::cli {
namespace {

constexpr std::size_t kWidth = 100;         // wrap help text before this column
constexpr std::size_t kSummaryColumn = 39;  // `deepcut --help`: summaries under their synopsis
constexpr std::size_t kHelpIndent = 8;      // `deepcut CMD --help`: argument text under its name

// `text` wrapped at word boundaries to kWidth, each line indented by `indent` spaces; "\n" in
// `text` starts a new line.
std::string wrap(const std::string& text, std::size_t indent) {
  std::string out, line;
  const std::string pad(indent, ' ');
  std::size_t start = 0;
  auto flush = [&] {
    out += pad + line + "\n";
    line.clear();
  };
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find_first_of(" \n", start), text.size());
    const std::string word = text.substr(start, end - start);
    if (!word.empty()) {
      if (!line.empty() && indent + line.size() + 1 + word.size() > kWidth) flush();
      line += (line.empty() ? "" : " ") + word;
    }
    if (end < text.size() && text[end] == '\n') flush();
    start = end + 1;
  }
  if (!line.empty()) flush();
  return out;
}

// The synopsis lines, each indented by `indent`.
std::string synopsis_lines(const CommandSpec& spec, std::size_t indent) {
  std::string out;
  std::size_t start = 0;
  while (start <= spec.synopsis.size()) {
    const std::size_t end = std::min(spec.synopsis.find('\n', start), spec.synopsis.size());
    out += std::string(indent, ' ') + spec.synopsis.substr(start, end - start) + "\n";
    start = end + 1;
  }
  return out;
}

// One argument: its name (and placeholder) on a line, its text wrapped below it.
std::string argument_entry(const std::string& name, const std::string& text) {
  return "  " + name + "\n" + wrap(text, kHelpIndent);
}

}  // namespace

const std::vector<CliCommand>& cli_commands() {
  static const std::vector<CliCommand> commands = [] {
    std::vector<CliCommand> out = {
        {&info_command(), run_info},       {&convert_command(), run_convert}, {&make_cactus_command(), run_make_cactus},
        {&apply_command(), run_apply},     {&cluster_command(), run_cluster}, {&softbody_command(), run_softbody},
        {&bench_command(), run_bench},
    };
    for (const OperationCommand& op : operation_commands())
      out.push_back({&op, [&op](const std::vector<std::string>& args) { return run_operation(op, args); }});
    return out;
  }();
  return commands;
}

const CliCommand* find_cli_command(const std::string& name) {
  for (const CliCommand& command : cli_commands())
    if (command.spec->name == name) return &command;
  return nullptr;
}

std::string usage() {
  std::string out = "usage: deepcut COMMAND [options]\n       deepcut COMMAND --help   (what COMMAND does, "
                    "its arguments, defaults and an example)\n\ncommands:\n";
  std::string names;
  for (const auto& command : operation_commands()) names += (names.empty() ? "" : ", ") + command.name;
  bool operations = false;
  for (const CliCommand& command : cli_commands()) {
    const bool operation = find_operation_command(command.spec->name) != nullptr;
    if (operation && !operations) out += "\noperation commands (the operations of history files: " + names + "):\n";
    operations = operations || operation;
    out += synopsis_lines(*command.spec, 2) + std::string(kSummaryColumn, ' ') + command.spec->summary + "\n";
  }
  out += "\nMODEL is a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh (loaded unrigged: one root\n"
         "joint, so every export is a rigged glTF)\n";
  out += "\nexit codes: 0 ok, 2 bad input or usage, 1 internal error\n";
  return out;
}

std::string command_help(const CommandSpec& spec) {
  std::string out = "usage: deepcut " + synopsis_lines(spec, 0) + "\n" + wrap(spec.summary, 0);
  if (!spec.details.empty()) out += "\n" + wrap(spec.details, 0);
  if (!spec.positionals.empty() || !spec.options.empty()) out += "\narguments:\n";
  for (const PositionalSpec& p : spec.positionals) out += argument_entry(p.name, p.help);
  for (const OptionSpec& o : spec.options) {
    std::string text = o.help;
    if (o.required) text += " (required)";
    if (!o.fallback.empty()) text += " (default: " + o.fallback + ")";
    out += argument_entry(o.value.empty() ? o.name : o.name + " " + o.value, text);
  }
  if (!spec.example.empty()) out += "\nexample:\n  " + spec.example + "\n";
  return out;
}

}  // namespace deepcut::cli
