// Typed exceptions of mtcal: each message says what was expected, what was found and where.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace mtcal {

// Where in an input a problem was found. line is 1-based; 0 means unknown.
struct SourceLocation {
  std::string file;
  int line = 0;
  std::string field;

  // "file:line: field 'key'" with the parts that are known.
  std::string describe() const;
};

// Text from an input as a message may show it: control and non-ASCII bytes escaped (\xNN), and
// cut to at most `max` characters with "…" so that a multi-megabyte cell cannot flood a terminal.
std::string printable(std::string_view text, std::size_t max = 60);

// Base class of every exception mtcal throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Malformed or inconsistent input data (machine files, CSV, command-line values).
class InputError : public Error {
 public:
  InputError(SourceLocation where, const std::string& what_happened);
  const SourceLocation& where() const noexcept { return where_; }

 private:
  SourceLocation where_;
};

// A request the model cannot satisfy (unknown parameter name, axis not in the topology ...).
class ModelError : public Error {
 public:
  using Error::Error;
};

}  // namespace mtcal
