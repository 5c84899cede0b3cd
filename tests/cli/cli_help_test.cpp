// SPDX-License-Identifier: MIT
// `deepcut --help` and `deepcut CMD --help` (app/cli/help.h): the top-level help lists exactly
// the commands that run, and each command's help names every option its parser accepts, with its
// meaning and default, the arguments and an example.
#include <gtest/gtest.h>

#include <set>
#include <sstream>
#include <string>

#include "help.h"
#include "tools.h"

namespace deepcut {
namespace {

using cli::cli_commands;
using cli::CliCommand;
using cli::CommandSpec;
using cli::OptionSpec;

// Runs of spaces and line breaks as one space, so wrapped text compares with the source text.
std::string squeeze(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const bool space = c == ' ' || c == '\n';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  return out;
}

// The text of the argument entry that starts with the line "  <head>", up to the next entry or
// section; empty when there is no such entry.
std::string entry(const std::string& help, const std::string& head) {
  const std::string start = "\n  " + head + "\n";
  const std::size_t at = help.find(start);
  if (at == std::string::npos) return "";
  std::size_t end = at + start.size();
  while (end < help.size() && help.compare(end, 8, std::string(8, ' ')) == 0) end = help.find('\n', end) + 1;
  return squeeze(help.substr(at + start.size(), end - at - start.size()));
}

// The words that start the synopsis lines of `deepcut --help` ("  cut MODEL ..." gives "cut").
std::set<std::string> listed_commands(const std::string& help) {
  std::set<std::string> out;
  std::istringstream lines(help);
  std::string line;
  while (std::getline(lines, line))
    if (line.size() > 2 && line.compare(0, 2, "  ") == 0 && line[2] >= 'a' && line[2] <= 'z')
      out.insert(line.substr(2, line.find(' ', 2) - 2));
  return out;
}

TEST(CliHelp, top_level_help_lists_exactly_the_commands_that_run) {
  const auto help = test::run_cli("--help");
  ASSERT_EQ(help.exit_code, 0) << help.err;
  std::set<std::string> table;
  for (const CliCommand& command : cli_commands()) {
    EXPECT_TRUE(table.insert(command.spec->name).second) << command.spec->name << " is listed twice";
    EXPECT_NE(help.out.find(command.spec->summary), std::string::npos) << command.spec->name;
    // It runs: its parser answers (an unknown option), not the dispatcher.
    const auto r = test::run_cli(command.spec->name + " --no-such-option");
    EXPECT_EQ(r.exit_code, 2) << command.spec->name;
    EXPECT_NE(r.err.find("unknown option --no-such-option"), std::string::npos) << command.spec->name << ": " << r.err;
  }
  EXPECT_EQ(listed_commands(help.out), table) << help.out;
  for (const char* name : {"info", "convert", "make-cactus", "apply", "cluster", "softbody", "bench", "cut", "tear",
                           "drill"})
    EXPECT_EQ(table.count(name), 1u) << name;
  const auto poke = test::run_cli("poke x.glb");
  EXPECT_EQ(poke.exit_code, 2);
  EXPECT_NE(poke.err.find("unknown command"), std::string::npos) << poke.err;
  EXPECT_EQ(table.count("poke"), 0u);
}

TEST(CliHelp, each_command_help_names_every_option_with_its_meaning_and_default) {
  for (const CliCommand& command : cli_commands()) {
    const CommandSpec& spec = *command.spec;
    const auto r = test::run_cli(spec.name + " --help");
    ASSERT_EQ(r.exit_code, 0) << spec.name << ": " << r.err;
    const std::string& help = r.out;
    EXPECT_EQ(help.rfind("usage: deepcut " + spec.name, 0), 0u) << help;
    EXPECT_NE(squeeze(help).find(squeeze(spec.summary)), std::string::npos) << spec.name;
    EXPECT_EQ(spec.example.rfind("deepcut " + spec.name + " ", 0), 0u) << spec.name << ": " << spec.example;
    EXPECT_NE(help.find("example:\n  " + spec.example + "\n"), std::string::npos) << help;
    for (const auto& p : spec.positionals) {
      EXPECT_NE(help.find(" " + p.name), std::string::npos) << spec.name << ": synopsis lacks " << p.name;
      EXPECT_NE(entry(help, p.name), "") << spec.name << ": " << p.name << " is not explained\n" << help;
    }
    for (const OptionSpec& o : spec.options) {
      const std::string head = o.value.empty() ? o.name : o.name + " " + o.value;
      const std::string text = entry(help, head);
      ASSERT_NE(text, "") << spec.name << ": " << head << " is not explained\n" << help;
      EXPECT_NE(text.find(squeeze(o.help)), std::string::npos) << spec.name << " " << o.name << ": " << text;
      if (!o.fallback.empty()) {
        EXPECT_NE(text.find("(default: " + squeeze(o.fallback) + ")"), std::string::npos) << spec.name << " " << o.name;
      }
      if (o.required) {
        EXPECT_NE(text.find("(required)"), std::string::npos) << spec.name << " " << o.name;
      }
      EXPECT_NE(help.substr(0, help.find("\n\n")).find(o.name), std::string::npos)
          << spec.name << ": synopsis lacks " << o.name;
    }
  }
}

TEST(CliHelp, the_parser_accepts_every_option_the_help_names) {
  // Each option alone after a MODEL that does not exist: the command gets past its parser and
  // fails later (a missing argument or the unreadable model), never on the option itself.
  const std::string missing = test::quote(std::string(DEEPCUT_ASSETS_DIR) + "/no-such-model.glb");
  for (const CliCommand& command : cli_commands())
    for (const OptionSpec& o : command.spec->options) {
      const std::string args = command.spec->name + " " + missing + " " + o.name + (o.value.empty() ? "" : " 1");
      const auto r = test::run_cli(args);
      EXPECT_EQ(r.exit_code, 2) << args;
      for (const char* refusal : {"unknown option", "takes no value", "needs a value"})
        EXPECT_EQ(r.err.find(refusal), std::string::npos) << args << ": " << r.err;
    }
}

TEST(CliHelp, cut_help_says_which_side_keep_positive_keeps) {
  const auto r = test::run_cli("cut --help");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(squeeze(r.out).find("positive keeps the side the normal N points to"), std::string::npos) << r.out;
  const auto tear = test::run_cli("tear -h");
  EXPECT_NE(squeeze(tear.out).find("handle point H, then its tip point T"), std::string::npos) << tear.out;
}

}  // namespace
}  // namespace deepcut
