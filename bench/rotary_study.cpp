// Study behind docs/rotary-axis.md: how far each rotary-axis estimator lands from the truth as
// probe noise grows, over many simulated probings of the seed's C-axis protocol. Prints the
// Markdown table. Usage: mtcal_rotary_study [trials]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/probing/sphere_probing.hpp"
#include "synthetic.hpp"

using namespace mtcal;

int main(int argc, char** argv) {
  const int trials = argc > 1 ? std::atoi(argv[1]) : 100;
  const double truth[4] = {0.012, -0.008, 25e-6, -40e-6};
  const char* names[4] = {"EX0C", "EY0C", "EA0C", "EB0C"};
  Machine m = mtcal::testing::nominal_machine("wCAYXfZt");
  for (int q = 0; q < 4; ++q) m.set_parameter(names[q], truth[q]);
  const auto axis = NominalRotaryAxis::from(m.axis('C'));
  std::printf(
      "| probe noise σ | estimator | RMS error EX0C µm | EY0C µm | EA0C µrad | EB0C µrad | mean reported u: EX0C µm | "
      "EA0C µrad |\n");
  std::printf("|---:|---|---:|---:|---:|---:|---:|---:|\n");
  struct Level {
    double noise_um;
    bool outlier;
  };
  for (const Level level : {Level{0.0, false}, Level{0.5, false}, Level{1.0, false}, Level{2.0, false},
                            Level{5.0, false}, Level{1.0, true}}) {
    const double noise_um = level.noise_um;
    double se[2][4] = {}, u_sum[2] = {}, ua_sum[2] = {};
    for (int t = 0; t < trials; ++t) {
      ProbingSimulation sim;
      sim.axis = 'C';
      for (int d = 0; d < 360; d += 10) sim.angles.push_back(d * std::numbers::pi / 180);
      sim.sphere = Point3(150, -40, 80);
      sim.noise = noise_um * 1e-3;
      sim.seed = static_cast<std::uint64_t>(t + 1);
      std::vector<MeasuredCentre> centres;
      for (const auto& ix : simulate_probing(m, sim))
        centres.push_back({ix.angle, sphere_centre(ix.contacts, sim.probing, "study").centre()});
      // A chip or dirt on the sphere at one indexation: a centre 25 um off.
      if (level.outlier) centres[7].centre += Point3(0.02, -0.012, 0.008);
      const auto tri = estimate_by_triples(axis, centres);
      const auto lsq = estimate_by_least_squares(axis, centres);
      const RotaryEstimate* est[2] = {&tri, &lsq};
      for (int e = 0; e < 2; ++e) {
        for (int q = 0; q < 4; ++q) se[e][q] += std::pow(est[e]->value[q] - truth[q], 2);
        u_sum[e] += est[e]->uncertainty[0];
        ua_sum[e] += est[e]->uncertainty[2];
      }
    }
    for (int e = 0; e < 2; ++e) {
      const double n = trials;
      std::printf("| %.1f µm%s | %s | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f |\n", noise_um,
                  level.outlier ? " + one 25 µm outlier" : "", e == 0 ? "triples, 2σ rule" : "least squares",
                  std::sqrt(se[e][0] / n) * 1e3, std::sqrt(se[e][1] / n) * 1e3, std::sqrt(se[e][2] / n) * 1e6,
                  std::sqrt(se[e][3] / n) * 1e6, u_sum[e] / n * 1e3, ua_sum[e] / n * 1e6);
    }
  }
  return 0;
}
