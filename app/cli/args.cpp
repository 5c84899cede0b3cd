// SPDX-License-Identifier: MIT
#include "args.h"

#include <cmath>
#include <sstream>

#include "deepcut/core/model.h"

namespace deepcut::cli {

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& flags, const std::set<std::string>& options) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    std::string a = argv[i];
    if (a.size() > 1 && a[0] == '-' && !(a.size() > 1 && (std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.'))) {
      std::string value;
      bool has_value = false;
      const auto eq = a.find('=');
      if (eq != std::string::npos) {
        value = a.substr(eq + 1);
        a = a.substr(0, eq);
        has_value = true;
      }
      if (flags.count(a)) {
        if (has_value) throw UsageError("option " + a + " takes no value");
        flags_.insert(a);
      } else if (options.count(a)) {
        if (!has_value) {
          if (i + 1 >= argv.size()) throw UsageError("option " + a + " needs a value");
          value = argv[++i];
        }
        values_[a] = value;
      } else {
        throw UsageError("unknown option " + a);
      }
    } else {
      positionals_.push_back(a);
    }
  }
}

namespace {
std::set<std::string> names_of(const CommandSpec& spec, bool with_value) {
  std::set<std::string> out;
  for (const OptionSpec& o : spec.options)
    if (o.value.empty() != with_value) out.insert(o.name);
  return out;
}
}  // namespace

Args::Args(const std::vector<std::string>& argv, const CommandSpec& spec)
    : Args(argv, names_of(spec, false), names_of(spec, true)) {}

CommandSpec with_synopsis(CommandSpec spec) {
  constexpr std::size_t kWidth = 100;  // wrap before this column, continuations indented by four
  std::vector<std::string> tokens = {spec.name};
  for (const PositionalSpec& p : spec.positionals) tokens.push_back(p.name);
  std::string group;
  for (std::size_t i = 0; i < spec.options.size(); ++i) {
    const OptionSpec& o = spec.options[i];
    const std::string text = o.value.empty() ? o.name : o.name + " " + o.value;
    group += (group.empty() ? "" : " | ") + text;
    if (o.or_next && i + 1 < spec.options.size()) continue;
    const bool required = o.required || (i > 0 && spec.options[i - 1].or_next && spec.options[i - 1].required);
    const bool alternatives = group.find(" | ") != std::string::npos;
    tokens.push_back(required ? (alternatives ? "(" + group + ")" : group) : "[" + group + "]");
    group.clear();
  }
  std::string out, line;
  for (const std::string& t : tokens) {
    if (!line.empty() && line.size() + 1 + t.size() > kWidth) {
      out += line + "\n";
      line = "   ";
    }
    line += (line.empty() ? "" : " ") + t;
  }
  spec.synopsis = out + line;
  return spec;
}

std::string number_text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

OptionSpec json_option(const std::string& what) {
  return {"--json", "", "print " + what + " as JSON on stdout instead of the text report", "", false, false};
}

std::vector<OptionSpec> output_options() {
  return {{"-o", "OUT", "the model to write: .glb (binary glTF) or .gltf (text glTF, buffers embedded); "
                        "written to a temporary file and renamed, so nothing is written on failure",
           "", true, false},
          {"--compress", "none|draco|meshopt",
           "compress the written meshes: none (plain glTF), draco (KHR_draco_mesh_compression: smallest, positions, normals and "
           "texture coordinates quantised) or meshopt (EXT_meshopt_compression: lossless); a reader must "
           "decode the extension",
           "none (plain glTF)", false, false}};
}

std::vector<OptionSpec> pose_options() {
  return {{"--time", "T",
           "seconds into the animation: the model is posed at this time, and every world-space argument "
           "refers to that pose (the edit still lands in bind space, so the result animates)",
           "the rest pose", false, false},
          {"--animation", "I",
           "index of the animation --time plays (0 is the first; -1 is the rest pose)",
           "0, or -1 when the model has no animation", false, false}};
}

std::string Args::value(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

namespace {
double parse_number(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v)) throw UsageError(option + ": '" + text + "' is not a finite number");
  return v;
}
}  // namespace

double Args::number(const std::string& name, double fallback) const {
  return has(name) ? parse_number(value(name), name) : fallback;
}

long long Args::integer(const std::string& name, long long fallback) const {
  if (!has(name)) return fallback;
  const std::string text = value(name);
  std::size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used, 10);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw UsageError(name + ": '" + text + "' is not a whole number");
  return v;
}

ExportOptions export_options(const Args& args) {
  ExportOptions options;
  if (args.has("--compress") && !parse_compression(args.value("--compress"), &options.compression))
    throw UsageError("--compress '" + args.value("--compress") + "': use none, draco or meshopt");
  return options;
}

std::string count_of(std::size_t n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

int animation_option(const Args& args, std::size_t count) {
  const long long animation = args.integer("--animation", count == 0 ? -1 : 0);
  if (animation < -1 || animation >= static_cast<long long>(count)) {
    const std::string range = count == 0 ? "only -1 (the rest pose) is valid"
                                         : "valid: -1 (the rest pose) to " + std::to_string(count - 1);
    throw UsageError("--animation " + std::to_string(animation) + ": the model has " + std::to_string(count) +
                     (count == 1 ? " animation; " : " animations; ") + range);
  }
  return static_cast<int>(animation);
}

int pose_animation(const Args& args, const Model& model) {
  const int animation = animation_option(args, model.animations.size());
  return args.has("--time") ? animation : -1;
}

std::vector<ImportProblem> pose_problems(const Args& args, const Model& model) {
  if (!args.has("--time") || !model.animations.empty()) return {};
  const std::string what =
      "--time " + args.value("--time") + ": the model has no animation, so the rest pose is used";
  return {{"time-without-animation", what, 1, {}}};
}

std::vector<double> Args::vector(const std::string& name, std::size_t count) const {
  std::vector<double> out;
  std::stringstream ss(value(name));
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(parse_number(item, name));
  if (out.size() != count)
    throw UsageError(name + " needs " + std::to_string(count) + " comma-separated numbers, got " + std::to_string(out.size()));
  return out;
}

}  // namespace deepcut::cli
