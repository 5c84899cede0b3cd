// SPDX-License-Identifier: MIT
#pragma once
/// @file errors.h
/// The one exception type of the library. Core never prints and never exits: callers catch
/// `Error` at the boundary (CLI: exit code 2 for input problems, 1 for internal ones).

#include <stdexcept>
#include <string>

namespace deepcut {

enum class ErrorCode {
  InvalidArgument,   ///< a parameter breaks a documented precondition (zero normal, radius 0)
  InvalidInput,      ///< a model file or mesh is malformed (bad JSON, NaN positions, bad indices)
  NonManifoldInput,  ///< an operation met topology it cannot handle
  MissingAttribute,  ///< a required attribute array is absent
  Io,                ///< a file could not be read or written
  InvariantViolated  ///< an internal consistency check failed (a bug, not bad input)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& what) : std::runtime_error(what), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

  /// True for errors caused by the caller's input (CLI exit code 2), false for bugs (exit 1).
  bool is_input_error() const noexcept { return code_ != ErrorCode::InvariantViolated; }

 private:
  ErrorCode code_;
};

}  // namespace deepcut
