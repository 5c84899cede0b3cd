// SPDX-License-Identifier: MIT
// deepcut: cut, tear and drill rigged glTF models from the command line.
// Exit codes: 0 success, 2 bad input or usage (one line on stderr), 1 internal error.
#include <algorithm>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "args.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/process_memory.h"
#include "help.h"

namespace {

// Errors stay on one stderr line whatever they quote (a file name or JSON string with a newline).
std::string one_line(const char* text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = ' ';
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  deepcut::keep_freed_memory();  // an operation writes into the pages the last one freed
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::cout << deepcut::cli::usage();
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  const deepcut::cli::CliCommand* cli_command = deepcut::cli::find_cli_command(command);
  const auto wants_help = [](const std::string& a) { return a == "--help" || a == "-h"; };
  if (cli_command && std::find_if(args.begin(), args.end(), wants_help) != args.end()) {
    std::cout << deepcut::cli::command_help(*cli_command->spec);
    return 0;
  }
  try {
    if (cli_command) return cli_command->run(args);
    std::cerr << "deepcut: unknown command '" << command << "' (see deepcut --help)\n";
    return 2;
  } catch (const deepcut::cli::UsageError& e) {
    std::cerr << "deepcut " << one_line(command.c_str()) << ": " << one_line(e.what()) << " (see deepcut --help)\n";
    return 2;
  } catch (const deepcut::Error& e) {
    // The library's messages name their operation ("drill: ..."); the line names it already.
    std::string message = one_line(e.what());
    if (message.rfind(command + ": ", 0) == 0) message.erase(0, command.size() + 2);
    std::cerr << "deepcut " << one_line(command.c_str()) << ": " << message << "\n";
    return e.is_input_error() ? 2 : 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "deepcut " << command << ": out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "deepcut " << one_line(command.c_str()) << ": internal error: " << one_line(e.what()) << "\n";
    return 1;
  }
}
