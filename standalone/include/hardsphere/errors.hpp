#pragma once
//! Typed errors: every message names the offending value and where it came from.
#include <stdexcept>
#include <string>

namespace hardsphere {

//! Invalid user input (options, data files, impossible requests). The CLI exits 2 on it.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

//! A data file that cannot be parsed; the message carries "file:line".
class FormatError : public InputError {
 public:
  FormatError(const std::string& file, long line, const std::string& what)
      : InputError(file + ":" + std::to_string(line) + ": " + what) {}
};

}  // namespace hardsphere
