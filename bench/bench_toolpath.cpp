// Benchmarks of the tool-path simulation on a generated program of 1 M short G1/G2/G3 blocks:
// parsing (against a getline + strtod baseline of the same text), interpolation, and the whole
// parse + interpolate + evaluate on the 3-axis example. items_per_second counts G-code blocks.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <sstream>
#include <string>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "synthetic.hpp"

namespace {

constexpr std::size_t kBlocks = 1'000'000;

// A serpentine of 1 mm steps across a 150 mm strip: a straight step up, a semicircle by I J,
// a straight step down, a semicircle by R; every block numbered, as CAM output is.
std::string generate_program() {
  std::string text = "%\n(generated: 1 M blocks of short G1 G2 G3 moves)\nN1 G21 G17 G90 G94\nN2 G0 X0 Y0 Z-5\n";
  text.reserve(kBlocks * 32);
  double x = 0, y = 0, dx = 1;
  for (std::size_t i = 0; i < kBlocks - 2; ++i) {
    if ((dx > 0 && x >= 150) || (dx < 0 && x <= 0)) dx = -dx;
    const double nx = x + dx;
    switch (i % 4) {
      case 0:
        fmt::format_to(std::back_inserter(text), "N{} G1 X{:.3f} Y{:.3f} F1200\n", i + 3, nx, y + 0.3);
        y += 0.3;
        break;
      case 1:
        fmt::format_to(std::back_inserter(text), "N{} G3 X{:.3f} Y{:.3f} I{:.3f} J0\n", i + 3, nx, y, dx / 2);
        break;
      case 2:
        fmt::format_to(std::back_inserter(text), "N{} G1 X{:.3f} Y{:.3f}\n", i + 3, nx, y - 0.3);
        y -= 0.3;
        break;
      default: fmt::format_to(std::back_inserter(text), "N{} G2 X{:.3f} Y{:.3f} R0.5\n", i + 3, nx, y); break;
    }
    x = nx;
  }
  text += "N1000001 M30\n%\n";
  return text;
}

struct Fixture {
  std::string text = generate_program();
  mtcal::Machine machine = mtcal::load_machine(MTCAL_EXAMPLES_DIR "/vmc-3axis.yaml");
  mtcal::ErrorModel model{machine};
  mtcal::GcodeOptions gcode;
  mtcal::ToolpathOptions options;
  Fixture() {
    gcode.axes = "XYZ";
    options.step = 0.5;
    options.origin = {-75, -20, -400, 0, 0, 0};
  }
};

const Fixture* fixture(std::string& error) {
  static std::unique_ptr<Fixture> f;
  static std::string err;
  static bool built = false;
  if (!built) {
    built = true;
    try {
      f = std::make_unique<Fixture>();
      // The program must be valid, or the figures measure an early error.
      const auto p = mtcal::parse_gcode(f->text, "generated.nc", f->gcode);
      if (p.moves.size() != kBlocks - 1) err = fmt::format("expected {} moves, found {}", kBlocks - 1, p.moves.size());
    } catch (const std::exception& e) {
      err = e.what();
    }
    if (!err.empty()) f.reset();
  }
  error = err;
  return f.get();
}

void BM_ToolpathParse(benchmark::State& state) {
  std::string error;
  const Fixture* f = fixture(error);
  if (!f) return state.SkipWithError(error.c_str());
  for (auto _ : state) {
    mtcal::GcodeReader reader(f->text, "generated.nc", f->gcode);
    mtcal::GcodeMove m;
    double sum = 0;
    while (reader.next(m)) sum += m.end[0];
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBlocks));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(f->text.size()));
}

// The naive way: a line at a time from an istringstream, each word's number by strtod. It
// checks nothing and computes no arc, so it is a floor for what a reader of the text costs.
void BM_ToolpathParseBaselineStrtod(benchmark::State& state) {
  std::string error;
  const Fixture* f = fixture(error);
  if (!f) return state.SkipWithError(error.c_str());
  for (auto _ : state) {
    std::istringstream in(f->text);
    std::string line;
    double sum = 0;
    std::size_t words = 0;
    while (std::getline(in, line)) {
      const char* p = line.c_str();
      while (*p) {
        if (*p == '(') {
          while (*p && *p != ')') ++p;
          if (*p) ++p;
          continue;
        }
        if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z')) {
          char* end = nullptr;
          const double v = std::strtod(p + 1, &end);
          sum += v;
          ++words;
          p = end > p + 1 ? end : p + 1;
          continue;
        }
        ++p;
      }
    }
    benchmark::DoNotOptimize(sum);
    benchmark::DoNotOptimize(words);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBlocks));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(f->text.size()));
}

// Interpolation alone, from moves parsed beforehand, into a chunk emptied every 64 k points.
void BM_ToolpathInterpolate(benchmark::State& state) {
  std::string error;
  const Fixture* f = fixture(error);
  if (!f) return state.SkipWithError(error.c_str());
  const auto program = mtcal::parse_gcode(f->text, "generated.nc", f->gcode);
  std::size_t points = 0;
  for (auto _ : state) {
    mtcal::ToolpathInterpolator interp(f->machine, f->options);
    mtcal::ToolpathChunk chunk;
    points = 0;
    for (const auto& m : program.moves) {
      if (!interp.start(m)) continue;
      while (!interp.fill(chunk, f->options.chunk)) {
        points += chunk.size();
        chunk.clear();
      }
      if (chunk.size() >= f->options.chunk) points += chunk.size(), chunk.clear();
    }
    points += chunk.size();
    benchmark::DoNotOptimize(points);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBlocks));
  state.counters["points"] = static_cast<double>(points);
}

// What `mtcal toolpath` does without writing: read, interpolate, evaluate, summarise.
void BM_ToolpathSimulate(benchmark::State& state) {
  std::string error;
  const Fixture* f = fixture(error);
  if (!f) return state.SkipWithError(error.c_str());
  mtcal::ToolpathOptions options = f->options;
  options.batch.threads = static_cast<int>(state.range(0));
  std::size_t points = 0;
  for (auto _ : state) {
    mtcal::GcodeReader reader(f->text, "generated.nc", f->gcode);
    const auto sum = mtcal::simulate_toolpath(f->model, reader, options);
    points = sum.points;
    benchmark::DoNotOptimize(sum.max_error);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kBlocks));
  state.counters["points"] = static_cast<double>(points);
}

void thread_args(benchmark::internal::Benchmark* b) {
  b->ArgName("threads");
  for (int t : mtcal::testing::thread_counts_to_compare()) b->Arg(t);
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_ToolpathParse)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ToolpathParseBaselineStrtod)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ToolpathInterpolate)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ToolpathSimulate)->Apply(thread_args);

}  // namespace
