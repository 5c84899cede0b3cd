// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/parameter_name.h
/// How an operation's argument checks name a parameter in their messages. Each check is written
/// once, in the operation; a front end that names its parameters otherwise (the command line's
/// flags, "--radius") passes its names in.

#include <functional>
#include <string>

namespace deepcut {

/// A parameter's name in messages, given its history key ("radius", docs/cli.md "History
/// files"); empty: the key itself.
using ParameterName = std::function<std::string(const std::string& key)>;

/// `name(key)`, or `key` when `name` is empty.
inline std::string parameter_name(const ParameterName& name, const std::string& key) {
  return name ? name(key) : key;
}

}  // namespace deepcut
