// HTML report of a compensation: what was written and what its numbers are, the error before and after, what the target
// cannot hold.
#pragma once

#include <string>
#include <vector>

#include "mtcal/io/compensation/output.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// inputs: (label, path) of the machine and parameter files, hashed into the summary block.
void write_compensation_report(const std::string& path, const std::string& command, const Machine& m,
                               const std::vector<std::pair<std::string, std::string>>& inputs,
                               const std::string& out_dir, const TargetOutput& out);

}  // namespace mtcal
