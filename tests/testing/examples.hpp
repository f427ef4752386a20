// Test helpers: the example machines (examples/machines) and the angle constants the tests share.
#pragma once

#include <numbers>
#include <string>

#include "mtcal/io/model/machine_file.hpp"

// Each test target defines MTCAL_EXAMPLES_DIR (tests/CMakeLists.txt): examples/machines.
namespace mtcal::testing {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = std::numbers::pi / 180.0;

// An example machine file, by name (e.g. "vmc-3axis.yaml").
inline Machine example(const std::string& name) { return load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + name); }
inline Machine vmc() { return example("vmc-3axis.yaml"); }
inline Machine hu40t() { return example("hu40t-wCBXfYZt.yaml"); }
// The probing plans and their artefacts (examples/plans/), with the trailing '/'.
inline const std::string kPlans = std::string(MTCAL_EXAMPLES_DIR) + "/../plans/";

}  // namespace mtcal::testing
