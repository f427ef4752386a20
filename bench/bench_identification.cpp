// Benchmarks of identification (issue targets): the HU40T SAMBA/TANGO example identified (<= 50 ms),
// the C(19,8) = 75,582-subset enumeration (<= 1 s), a 1,000-run Monte Carlo (<= 10 s).
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/SVD>

#include "mtcal/identification/identification.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"

namespace {

using namespace mtcal;

const std::vector<std::string> kLocation{"EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C",  "EA0C",  "EB0C",
                                         "EX0B", "EZ0B", "EA0B", "EC0B", "EXX.1", "EYY.1", "EZZ.1"};
const std::vector<std::string> kNineteen{"EX0C", "EY0C", "EA0C", "EB0C", "EC0C", "EX0B", "EZ0B", "EA0B", "EB0B", "EC0B",
                                         "EX0X", "EB0X", "EC0X", "EY0Y", "EA0Y", "EC0Y", "EZ0Z", "EA0Z", "EB0Z"};

struct IdentificationSetup {
  Machine truth, prior;
  ProbingPlan plan;
  ProbingPlan measurements;
  IdentificationOptions options;
};

const IdentificationSetup& setup() {
  static const IdentificationSetup s = [] {
    IdentificationSetup t;
    t.truth = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
    t.prior = t.truth;
    for (const auto& n : kLocation) t.prior.set_parameter(n, 0.0);
    t.plan = read_probing_csv(t.truth, std::string(MTCAL_EXAMPLES_DIR) + "/../plans/hu40t-samba-tango.csv");
    SimulationOptions so;
    so.noise = 1e-3;
    so.seed = 7;
    so.artefact_error = 0.05;
    so.scale_bars = {{"1", "2", 304.8}};
    t.measurements = simulate_probing(t.truth, t.plan, so).measurements;
    t.options.estimate = kLocation;
    t.options.scale_bars = so.scale_bars;
    return t;
  }();
  return s;
}

// 189 residuals, 33 unknowns (14 parameters, 6 balls, 1 facet), from the prior with them at zero.
void BM_Identify_Hu40t(benchmark::State& state) {
  const IdentificationSetup& s = setup();
  for (auto _ : state) benchmark::DoNotOptimize(identify(s.prior, s.measurements, s.options).final_cost);
}
BENCHMARK(BM_Identify_Hu40t)->Unit(benchmark::kMillisecond);

// Every 8-subset of the 19 location errors with the tool offsets always in (Viprey section 4).
void BM_Subsets_19choose8(benchmark::State& state) {
  const IdentificationSetup& s = setup();
  SubsetOptions so;
  so.candidates = kNineteen;
  so.always = {"EXt", "EYt", "EZt"};
  so.choose = 8;
  so.threads = static_cast<int>(state.range(0));
  SubsetAnalysis a;
  for (auto _ : state) benchmark::DoNotOptimize((a = full_rank_subsets(s.truth, s.plan, so, s.options)).full_rank);
  state.counters["full_rank"] = static_cast<double>(a.full_rank);
  state.counters["examined"] = static_cast<double>(a.examined);
}
BENCHMARK(BM_Subsets_19choose8)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Baseline in the same run: one SVD rank test per subset, on 1/100 of the subsets (the first
// 756 in lexicographic order), reported per subset for the ratio.
void BM_Subsets_SvdPerSubset_Baseline(benchmark::State& state) {
  const IdentificationSetup& s = setup();
  std::size_t done = 0;
  for (auto _ : state) {
    std::size_t count = 0, full = 0;
    std::vector<std::size_t> idx{0, 1, 2, 3, 4, 5, 6, 7};
    while (count < 756) {
      IdentificationOptions o = s.options;
      o.estimate = {"EXt", "EYt", "EZt"};
      for (std::size_t i : idx) o.estimate.push_back(kNineteen[i]);
      full += identifiability(s.truth, s.plan, o).unidentifiable.empty();
      ++count;
      int k = 7;
      while (k >= 0 && idx[static_cast<std::size_t>(k)] == kNineteen.size() - 8 + static_cast<std::size_t>(k)) --k;
      if (k < 0) break;
      ++idx[static_cast<std::size_t>(k)];
      for (std::size_t j = static_cast<std::size_t>(k) + 1; j < 8; ++j) idx[j] = idx[j - 1] + 1;
    }
    done = count;
    benchmark::DoNotOptimize(full);
  }
  state.counters["subsets"] = static_cast<double>(done);
}
BENCHMARK(BM_Subsets_SvdPerSubset_Baseline)->Unit(benchmark::kMillisecond)->Iterations(1);

// 1,000 runs of re-drawn noise, each identified again; argument: threads.
void BM_MonteCarlo_1000(benchmark::State& state) {
  const IdentificationSetup& s = setup();
  const IdentificationResult r = identify(s.prior, s.measurements, s.options);
  MonteCarloOptions mc;
  mc.runs = 1000;
  mc.threads = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(monte_carlo(s.prior, s.measurements, s.options, r, mc).stdev.data());
}
BENCHMARK(BM_MonteCarlo_1000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
