// SPDX-License-Identifier: MIT
// The command line discovers its tools from the plugin registry (plugins/, DEEPCUT_TOOL_PLUGINS):
// every registered sub-command is listed by `deepcut --help`, has its own `--help`, and runs
// through the registry; the registry refuses ambiguous entries.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/tool_registry.h"
#include "tools.h"

namespace deepcut {
namespace {

using plugins::builtin_tools;
using plugins::ToolCommand;
using plugins::ToolInfo;
using plugins::ToolRegistry;

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

TEST(ToolRegistryCli, the_operation_tools_are_registered_with_their_commands) {
  std::set<std::string> commands;
  for (const ToolInfo& info : builtin_tools().list())
    for (const ToolCommand& command : info.commands) commands.insert(command.name);
  // The operations a history file names are each a tool whose command has the same name.
  for (const char* op : {"cut", "tear", "drill"}) {
    const ToolInfo* info = builtin_tools().find(op);
    ASSERT_NE(info, nullptr) << op;
    ASSERT_FALSE(info->commands.empty()) << op;
    EXPECT_EQ(info->commands.front().name, op);
    EXPECT_EQ(commands.count(op), 1u) << op;
    // The command line is built without the studio: no interactive tools in its registry.
    EXPECT_FALSE(info->create) << op;
  }
}

TEST(ToolRegistryCli, help_lists_every_registered_command) {
  const auto help = test::run_cli("--help");
  ASSERT_EQ(help.exit_code, 0) << help.err;
  EXPECT_NE(help.out.find("tool commands (registered by the tool plugins: " + builtin_tools().ids() + "):"), std::string::npos) << help.out;
  for (const ToolInfo& info : builtin_tools().list())
    for (const ToolCommand& command : info.commands) {
      EXPECT_NE(help.out.find("  " + first_line(command.synopsis) + "\n"), std::string::npos) << command.name;
      EXPECT_NE(help.out.find(command.summary), std::string::npos) << command.name;
      // Its own --help shows just its synopsis.
      const auto own = test::run_cli(command.name + " --help");
      EXPECT_EQ(own.exit_code, 0) << own.err;
      EXPECT_EQ(first_line(own.out), "usage: deepcut " + first_line(command.synopsis)) << own.out;
    }
}

TEST(ToolRegistryCli, registered_commands_run_through_the_registry) {
  // Without a model each command refuses the way its plugin says (exit 2, its own name first).
  for (const ToolInfo& info : builtin_tools().list())
    for (const ToolCommand& command : info.commands) {
      const auto r = test::run_cli(command.name);
      EXPECT_EQ(r.exit_code, 2) << command.name;
      EXPECT_EQ(r.err.rfind("deepcut " + command.name + ": ", 0), 0u) << r.err;
      EXPECT_EQ(r.err.find("unknown command"), std::string::npos) << r.err;
    }
}

TEST(ToolRegistryCli, the_registry_refuses_ambiguous_entries) {
  const auto run = [](const std::vector<std::string>&) { return 0; };
  ToolRegistry r;
  r.add({"a", "A", {{"a", "a MODEL", "does a", run}}, {}});
  EXPECT_NE(r.find_command("a"), nullptr);
  EXPECT_EQ(r.find_command("b"), nullptr);
  EXPECT_THROW(r.add({"a", "again", {{"a2", "a2", "", run}}, {}}), Error);  // id taken
  EXPECT_THROW(r.add({"b", "B", {{"a", "a", "", run}}, {}}), Error);        // command taken
  EXPECT_THROW(r.add({"d", "D", {{"", "", "", run}}, {}}), Error);          // unnamed command
  EXPECT_THROW(r.add({"", "E", {{"e", "e", "", run}}, {}}), Error);         // no id
  EXPECT_EQ(r.ids(), "a");
}

}  // namespace
}  // namespace deepcut
