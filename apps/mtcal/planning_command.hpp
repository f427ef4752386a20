// mtcal plan and probe-log (cmd_planning.cpp): probing plan design, its program and the contacts back.
#pragma once

#include <vector>

#include "common.hpp"

namespace mtcal::cli {

std::vector<Command> add_planning_commands(CLI::App& app);

}  // namespace mtcal::cli
