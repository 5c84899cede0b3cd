// SPDX-License-Identifier: MIT
// The command line's operation commands (app/cli/operation_command.h): every history operation
// has its command, `deepcut --help` lists each, each has its own `--help` and runs through the
// one runner; the plugin registry refuses ambiguous entries.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/formats.h"
#include "operation_command.h"
#include "tools.h"

namespace deepcut {
namespace {

using cli::operation_commands;
using cli::OperationCommand;

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

TEST(OperationCommandsCli, every_history_operation_has_its_command) {
  std::set<std::string> commands;
  for (const OperationCommand& command : operation_commands()) commands.insert(command.name);
  // The operations a history file names are each a command of the same name.
  for (const char* op : {"cut", "tear", "drill"}) {
    const OperationCommand* command = cli::find_operation_command(op);
    ASSERT_NE(command, nullptr) << op;
    EXPECT_EQ(command->name, op);
    EXPECT_EQ(commands.count(op), 1u) << op;
    EXPECT_TRUE(command->parse) << op;
  }
  EXPECT_EQ(commands.size(), operation_commands().size()) << "a command is listed twice";
  EXPECT_EQ(cli::find_operation_command("poke"), nullptr);
}

TEST(OperationCommandsCli, help_lists_every_operation_command) {
  const auto help = test::run_cli("--help");
  ASSERT_EQ(help.exit_code, 0) << help.err;
  EXPECT_NE(help.out.find("operation commands (the operations of history files: cut, tear, drill):"), std::string::npos)
      << help.out;
  EXPECT_EQ(help.out.find("\n  poke"), std::string::npos) << "help lists no command that does not run: " << help.out;
  for (const OperationCommand& command : operation_commands()) {
    EXPECT_NE(help.out.find("  " + first_line(command.synopsis) + "\n"), std::string::npos) << command.name;
    EXPECT_NE(help.out.find(command.summary), std::string::npos) << command.name;
    // Its own --help shows just its synopsis.
    const auto own = test::run_cli(command.name + " --help");
    EXPECT_EQ(own.exit_code, 0) << own.err;
    EXPECT_EQ(first_line(own.out), "usage: deepcut " + first_line(command.synopsis)) << own.out;
  }
}

TEST(OperationCommandsCli, operation_commands_run_through_the_runner) {
  // Without a model each command refuses (exit 2, its own name first).
  for (const OperationCommand& command : operation_commands()) {
    const auto r = test::run_cli(command.name);
    EXPECT_EQ(r.exit_code, 2) << command.name;
    EXPECT_EQ(r.err.rfind("deepcut " + command.name + ": ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find("unknown command"), std::string::npos) << r.err;
  }
}

TEST(OperationCommandsCli, the_plugin_registry_refuses_ambiguous_entries) {
  const auto read = [](const std::string&) { return Model(); };
  plugins::FormatRegistry r;
  r.add({"a", {"a"}, read});
  EXPECT_NE(r.find("a"), nullptr);
  EXPECT_EQ(r.find("b"), nullptr);
  EXPECT_THROW(r.add({"a", {"a2"}, read}), Error);  // id taken
  EXPECT_THROW(r.add({"b", {"a"}, read}), Error);   // extension taken
  EXPECT_THROW(r.add({"d", {""}, read}), Error);    // unnamed extension
  EXPECT_THROW(r.add({"", {"e"}, read}), Error);    // no id
  EXPECT_THROW(r.add({"f", {"f"}, {}}), Error);     // no reader
  EXPECT_EQ(r.ids(), "a");
}

}  // namespace
}  // namespace deepcut
