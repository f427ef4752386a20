// Synthetic machines and configurations with known ground truth, for tests and benchmarks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal::testing {

// A nominal machine of any topology (no errors), axes along their letters' directions, linear
// travels [-400, 400] mm, rotary [-120, 120] deg (C: [-360, 360]), rotary axis points off the
// origin, tool length 120 mm, workpiece origin off the origin. reversed: every axis runs the
// other way (direction -x, -y, -z).
Machine nominal_machine(const std::string& topology, bool reversed = false);

// Gives every parameter (each motion error as a cubic with reversal, every location and mounting
// error) a random value of realistic size times scale: about 5 um and 20 urad over the travel.
void randomize_errors(Machine& m, std::uint64_t seed, double scale = 1.0);

// Random joint configurations inside the travels, row-major n x axes (internal units), and
// random directions of motion (+1/-1) if dir is not null.
std::vector<double> random_configurations(const Machine& m, std::size_t n, std::uint64_t seed,
                                          std::vector<std::int8_t>* dir = nullptr);

}  // namespace mtcal::testing
