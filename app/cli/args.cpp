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
