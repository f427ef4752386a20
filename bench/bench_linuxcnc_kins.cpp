// Cost of one kinematicsInverse and one kinematicsForward of the module that
// `mtcal compensate --format linuxcnc-kins` writes, per example machine: the generated C compiled
// (-O2, the system C compiler) as a shared object and called through dlopen, on 64 poses spread
// over the travel; baseline in the same run: one evaluation of the C++ model (ErrorModel::actual_pose).
// Run: mtcal_kins_bench --benchmark_min_time=0.2 ; share of a 1 ms servo period = ns / 1e6.
#include <benchmark/benchmark.h>
#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "mtcal/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "synthetic.hpp"

using namespace mtcal;
namespace fs = std::filesystem;

namespace {

using InverseFn = int (*)(const double*, double, double*, int*, double*);
using ForwardFn = int (*)(const double*, double, double*);

struct Module {
  InverseFn inverse = nullptr;
  ForwardFn forward = nullptr;
  std::vector<std::vector<double>> worlds, joints;
  double tool_length = 0.0;
  Machine machine;
};

Module load(const char* file) {
  Module mod;
  mod.machine = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + file);
  CompensationOptions o;
  o.residual_points = 2;
  const LinuxcncKins k = compensate_linuxcnc_kins(mod.machine, o);
  const fs::path dir = fs::temp_directory_path() / fmt::format("mtcal-kins-bench-{}-{}", ::getpid(), std::string(file).substr(0, 4));
  fs::create_directories(dir);
  std::ofstream(dir / "module.c") << linuxcnc_kins_source(k);
  const fs::path so = dir / "module.so";
  const std::string cmd = fmt::format("{} -std=c99 -O2 -fPIC -shared -DMTCAL_KINS_STANDALONE '-DMTK_MODULE=\"{}\"' {} -o {} -lm",
                                      MTCAL_C_COMPILER, (dir / "module.c").string(), MTCAL_KINS_EXPORT, so.string());
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
  void* h = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) throw std::runtime_error(dlerror());
  mod.inverse = reinterpret_cast<InverseFn>(dlsym(h, "mtk_export_inverse"));
  mod.forward = reinterpret_cast<ForwardFn>(dlsym(h, "mtk_export_forward"));
  const CommandedJointSolver s(mod.machine);
  mod.tool_length = mod.machine.tool.length;
  const std::size_t n = mod.machine.axes.size();
  const auto q = mtcal::testing::random_configurations(mod.machine, 64, 5);
  std::vector<std::size_t> slot(n, 0);
  std::size_t next = 0;
  for (const char c : k.coordinates)
    if (c == 'A' || c == 'B' || c == 'C') slot[*mod.machine.axis_index(c)] = next++;
  for (std::size_t r = 0; r < 64; ++r) {
    const CommandedPose p = s.nominal_forward({q.data() + r * n, n}, mod.tool_length);
    std::vector<double> w(3 + s.rotary_count());
    for (int i = 0; i < 3; ++i) w[static_cast<std::size_t>(i)] = p.point[i];
    for (std::size_t j = 0; j < s.rotary_count(); ++j) w[3 + slot[s.rotary_axes()[j]]] = p.rotary[j] * 180.0 / std::numbers::pi;
    std::vector<double> jt(n);
    int it = 0;
    double res = 0.0;
    if (mod.inverse(w.data(), mod.tool_length, jt.data(), &it, &res) != 0) throw std::runtime_error("inverse failed");
    mod.worlds.push_back(w);
    mod.joints.push_back(jt);
  }
  return mod;
}

const Module& module(int i) {
  static const char* files[] = {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"};
  static std::vector<Module> mods = [] {
    std::vector<Module> v;
    for (const char* f : files) v.push_back(load(f));
    return v;
  }();
  return mods[static_cast<std::size_t>(i)];
}

void BM_KinsInverse(benchmark::State& state) {
  const Module& m = module(static_cast<int>(state.range(0)));
  std::vector<double> j(m.machine.axes.size());
  int it = 0;
  double res = 0.0;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.inverse(m.worlds[i].data(), m.tool_length, j.data(), &it, &res));
    benchmark::DoNotOptimize(j.data());
    i = (i + 1) & 63;
  }
  state.SetLabel(m.machine.topology.chain);
}

void BM_KinsForward(benchmark::State& state) {
  const Module& m = module(static_cast<int>(state.range(0)));
  std::vector<double> w(6);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.forward(m.joints[i].data(), m.tool_length, w.data()));
    benchmark::DoNotOptimize(w.data());
    i = (i + 1) & 63;
  }
  state.SetLabel(m.machine.topology.chain);
}

// Baseline: one evaluation of the actual pose by the C++ library.
void BM_ModelActualPose(benchmark::State& state) {
  const Module& m = module(static_cast<int>(state.range(0)));
  const ErrorModel model(m.machine);
  const std::size_t n = m.machine.axes.size();
  const auto q = mtcal::testing::random_configurations(m.machine, 64, 5);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.actual_pose({q.data() + i * n, n}));
    i = (i + 1) & 63;
  }
  state.SetLabel(m.machine.topology.chain);
}

}  // namespace

BENCHMARK(BM_KinsInverse)->DenseRange(0, 3);
BENCHMARK(BM_KinsForward)->DenseRange(0, 3);
BENCHMARK(BM_ModelActualPose)->DenseRange(0, 3);
BENCHMARK_MAIN();
