// Synthetic machines and configurations with known ground truth, for tests and benchmarks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {
struct MeasuredCentre;  // mtcal/probing/rotary_axis.hpp (not included: its Histogram meets volumetric.hpp's)
}

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

// Sphere centres of n indexations of a rotary axis about +z (one per 360/n degrees) on a slightly
// tilted, offset circle (radius 120 mm, 80 mm above the axis point (0.01, -0.02, 0)) with
// normal noise of noise_sd mm on every coordinate.
std::vector<MeasuredCentre> circle_centres(std::size_t n, std::uint64_t seed = 5, double noise_sd = 1e-3);

// Thread counts a benchmark compares: 1 and every hardware thread (just 1 on one core).
std::vector<int> thread_counts_to_compare();

}  // namespace mtcal::testing
