// placeholder
#include "common.hpp"
namespace mtcal::cli {
std::vector<Command> add_prediction_commands(CLI::App&) { return {}; }
}  // namespace mtcal::cli
