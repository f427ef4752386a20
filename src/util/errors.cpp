#include "mtcal/util/errors.hpp"

namespace mtcal {

std::string SourceLocation::describe() const {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line > 0) s += ":" + std::to_string(line);
  if (!field.empty()) s += ": field '" + field + "'";
  return s;
}

InputError::InputError(SourceLocation where, const std::string& what_happened)
    : Error(where.describe() + ": " + what_happened), where_(std::move(where)) {}

}  // namespace mtcal
