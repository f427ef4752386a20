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

// A resource limit an input or a request goes beyond (docs/reliability.md): the input size, the
// memory or time a computation is estimated to need, the size of an output. The program that
// set the limit knows how to raise it (mtcal names its option).
enum class Limit { InputSize, Memory, Time, OutputSize };
class LimitError : public InputError {
 public:
  LimitError(Limit limit, SourceLocation where, const std::string& what_happened)
      : InputError(std::move(where), what_happened), limit_(limit) {}
  Limit limit() const noexcept { return limit_; }

 private:
  Limit limit_;
};

// "48.0 GB", "256 MiB"-like figures for messages: bytes with a binary prefix (KiB MiB GiB TiB).
std::string format_bytes(double bytes);
// "3.2 s", "2.5 h", "41 years" for messages.
std::string format_seconds(double seconds);

// A request the model cannot satisfy (unknown parameter name, axis not in the topology ...).
class ModelError : public Error {
 public:
  using Error::Error;
};

}  // namespace mtcal
