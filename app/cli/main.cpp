// SPDX-License-Identifier: MIT
// deepcut: cut, tear and drill rigged glTF models from the command line.
// Exit codes: 0 success, 2 bad input or usage (one line on stderr), 1 internal error.
#include <algorithm>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "commands.h"
#include "deepcut/core/errors.h"
#include "args.h"
#include "operation_command.h"

namespace {

// The app's own commands; the operation commands follow from operation_commands() (usage()).
const char* kCommands =
    "  info MODEL [--json]                  counts, edges, bounding box and problems of a model\n"
    "  convert MODEL -o OUT [--json]        import, weld and export (.gltf <-> .glb)\n"
    "  make-cactus -o OUT [--triangles N]   write the project's rigged test cactus (default 25300 triangles)\n"
    "  apply MODEL HISTORY.json -o OUT [--json]   replay a list of operations\n"
    "  cluster MODEL (--radius RHO | --particles N) [--cover F] [--json]\n"
    "                                       soft-body particles of radius RHO (rest pose): counts, timing\n"
    "  softbody MODEL --poke X,Y,Z [--radius R] [--impulse IX,IY,IZ | --speed S] [--frames N] [--dt DT]\n"
    "      [--rho RHO | --particles N] [--stiffness K] [--damping C] [--mass M] [--time T] [--animation I]\n"
    "      [--animate] [--json]\n"
    "                                       poke the soft body, step N frames, report max displacement\n"
    "  bench [--json] [--quick]             the benchmark suite, with VTK peers measured in the same run\n";

constexpr std::size_t kSummaryColumn = 39;

// The whole usage text: the app's commands, then the operation commands (synopsis lines
// indented by two, the summary in its own line at kSummaryColumn, as the app's own).
std::string usage() {
  std::string out = "usage: deepcut COMMAND [options]\n\ncommands:\n";
  out += kCommands;
  std::string names;
  for (const auto& command : deepcut::cli::operation_commands()) names += (names.empty() ? "" : ", ") + command.name;
  out += "\noperation commands (the operations of history files: " + names + "):\n";
  for (const auto& command : deepcut::cli::operation_commands()) {
    std::size_t start = 0;
    while (start <= command.synopsis.size()) {
      const std::size_t end = std::min(command.synopsis.find('\n', start), command.synopsis.size());
      out += "  " + command.synopsis.substr(start, end - start) + "\n";
      start = end + 1;
    }
    out += std::string(kSummaryColumn, ' ') + command.summary + "\n";
  }
  out += "\nMODEL is a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh (loaded unrigged: one root\n"
         "joint, so every export is a rigged glTF)\n";
  out += "\nconvert, make-cactus, apply and the operation commands take --compress draco|meshopt: the\n"
         "output's meshes Draco compressed (KHR_draco_mesh_compression, quantised) or meshopt compressed\n"
         "(EXT_meshopt_compression, lossless); default none\n";
  out += "\nexit codes: 0 ok, 2 bad input or usage, 1 internal error\n";
  return out;
}

// Errors stay on one stderr line whatever they quote (a file name or JSON string with a newline).
std::string one_line(const char* text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = ' ';
  return out;
}

// The lines of usage() that describe `command` (its synopsis, continuation and description lines),
// or an empty string for an unknown command.
std::string command_usage(const std::string& command) {
  std::string out;
  bool inside = false;
  std::size_t start = 0;
  const std::string usage = ::usage();
  while (start < usage.size()) {
    const std::size_t end = usage.find('\n', start);
    const std::string line = usage.substr(start, end - start);
    start = end == std::string::npos ? usage.size() : end + 1;
    const bool synopsis = line.size() > 2 && line.compare(0, 2, "  ") == 0 && line[2] != ' ';
    if (synopsis) inside = line.compare(2, command.size() + 1, command + " ") == 0;
    else if (line.empty()) inside = false;
    if (inside) out += line + "\n";
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    std::cout << usage();
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  const std::string usage = command_usage(command);
  const auto wants_help = [](const std::string& a) { return a == "--help" || a == "-h"; };
  if (!usage.empty() && std::find_if(args.begin(), args.end(), wants_help) != args.end()) {
    std::cout << "usage: deepcut " << usage.substr(2);
    return 0;
  }
  try {
    if (command == "info") return deepcut::cli::run_info(args);
    if (command == "convert") return deepcut::cli::run_convert(args);
    if (command == "make-cactus") return deepcut::cli::run_make_cactus(args);
    if (command == "apply") return deepcut::cli::run_apply(args);
    if (command == "bench") return deepcut::cli::run_bench(args);
    if (command == "cluster") return deepcut::cli::run_cluster(args);
    if (command == "softbody") return deepcut::cli::run_softbody(args);
    if (const auto* operation = deepcut::cli::find_operation_command(command))
      return deepcut::cli::run_operation(*operation, args);
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
