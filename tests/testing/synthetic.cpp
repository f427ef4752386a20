#include "synthetic.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal::testing {

Machine nominal_machine(const std::string& topology, bool reversed) {
  std::string y = "mtcal_machine: 1\nname: synthetic " + topology + "\ntopology: " + topology +
                  "\nunits: {length: mm, angle: deg}\naxes:\n";
  int rotary = 0;
  for (char c : topology) {
    if (c == 'w' || c == 'f' || c == 't') continue;
    const bool linear = c == 'X' || c == 'Y' || c == 'Z';
    const std::string dir =
        fmt::format("{}{}", reversed ? '-' : '+', static_cast<char>('x' + (linear ? c - 'X' : c - 'A')));
    if (linear) {
      y += fmt::format("  {}: {{direction: {}, travel: [-400, 400], point: [{}, {}, {}]}}\n", c, dir, 10 * (c - 'X'),
                       -20, 30);
    } else {
      const double lim = c == 'C' ? 360 : 120;
      y += fmt::format("  {}: {{direction: {}, travel: [{}, {}], point: [{}, {}, {}]}}\n", c, dir, -lim, lim,
                       15 + 40 * rotary, -25 + 10 * rotary, 60 - 35 * rotary);
      ++rotary;
    }
  }
  y += "tool: {length: 120, spindle_point: [5, -3, 250]}\nworkpiece: {origin: [40, -30, 20]}\n";
  return parse_machine(y, std::string("synthetic:") + topology + (reversed ? " reversed" : ""));
}

void randomize_errors(Machine& m, std::uint64_t seed, double scale) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Size of an error value over the travel: 5 um for translations, 20 urad for rotations.
  const auto params = m.parameters();
  for (std::size_t i = 0; i < params.size(); ++i) {
    const auto& p = params[i];
    const bool rot = is_rotation(p.error.component);
    double size = rot ? 20e-6 : 5e-3;
    // Coefficient i of a polynomial is divided by (half travel)^i so every term stays of that size.
    const auto slash = p.unit.find('/');
    if (slash != std::string::npos) {
      const bool per_rad = p.unit.find("/rad") != std::string::npos;
      const auto caret = p.unit.find('^');
      const int power = caret == std::string::npos ? 1 : p.unit[caret + 1] - '0';
      size /= std::pow(per_rad ? 2.0 : 400.0, power);
    }
    m.set_parameter(i, size * scale * u(rng));
  }
}

std::vector<double> random_configurations(const Machine& m, std::size_t n, std::uint64_t seed,
                                          std::vector<std::int8_t>* dir) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t k = m.axes.size();
  std::vector<double> q(n * k);
  if (dir) dir->resize(n * k);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < k; ++j) {
      const auto& ax = m.axes[j];
      const double lo = ax.travel ? ax.travel->min : -std::numbers::pi;
      const double hi = ax.travel ? ax.travel->max : std::numbers::pi;
      q[i * k + j] = lo + (hi - lo) * u(rng);
      if (dir) (*dir)[i * k + j] = u(rng) < 0.5 ? -1 : 1;
    }
  return q;
}

std::vector<MeasuredCentre> circle_centres(std::size_t n, std::uint64_t seed, double noise_sd) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sd);
  const Point3 axis_point(0.01, -0.02, 0.0), normal = Point3(3e-5, -2e-5, 1.0).normalized();
  const Point3 u = normal.cross(Point3::UnitX()).normalized(), v = normal.cross(u);
  std::vector<MeasuredCentre> out;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    const Point3 p = axis_point + 120.0 * (std::cos(a) * u + std::sin(a) * v) + 80.0 * normal;
    const double dx = noise(rng), dy = noise(rng), dz = noise(rng);  // a fixed order of draws
    out.push_back({a, p + Point3(dx, dy, dz)});
  }
  return out;
}

std::vector<int> thread_counts_to_compare() {
  const int all = static_cast<int>(hardware_threads());
  return all > 1 ? std::vector<int>{1, all} : std::vector<int>{1};
}

}  // namespace mtcal::testing
