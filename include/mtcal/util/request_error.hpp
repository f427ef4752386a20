// A refusal located in the data whose cure is another value of one of the request's parameters.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mtcal/util/errors.hpp"

namespace mtcal {

// Thrown where the data (a program's block, a controller's table) cannot be processed with the
// values the request gave: located in the data, with the parameters to change as the library
// names them ("step", "angle step"), so that a program that took them from its options can name
// those (mtcal: rethrow_for_options adds "(--step, --angle-step)"). The message stays in the
// data's words.
class RequestError : public InputError {
 public:
  RequestError(SourceLocation where, const std::string& what_happened, std::vector<std::string> causes)
      : InputError(std::move(where), what_happened), causes_(std::move(causes)) {}
  const std::vector<std::string>& causes() const noexcept { return causes_; }

 private:
  std::vector<std::string> causes_;
};

}  // namespace mtcal
