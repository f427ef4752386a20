// Streamed evaluation: the same errors as ErrorModel::evaluate one by one, in any chunk size, grid order, extremes,
// non-finite errors.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::hu40t;

// Every configuration and error of a stream, gathered from its chunks.
struct Gathered {
  std::vector<std::size_t> first;
  std::vector<double> q, e;
  std::vector<std::int8_t> dir;
};
StreamSummary gather(const ErrorModel& model, const ConfigurationSource& source, std::size_t chunk, Gathered& g) {
  StreamOptions o;
  o.chunk = chunk;
  o.threads = 2;
  return evaluate_stream(
      model, source,
      [&](const ErrorChunk& c) {
        g.first.push_back(c.first);
        g.q.insert(g.q.end(), c.q.begin(), c.q.end());
        g.dir.insert(g.dir.end(), c.dir.begin(), c.dir.end());
        g.e.insert(g.e.end(), c.error.begin(), c.error.end());
      },
      o);
}

TEST(ErrorStream, GridEqualsPointByPointEvaluationInAnyChunkSize) {
  const Machine m = hu40t();
  const ErrorModel model(m);
  const GridValues grid = parse_grid(m, "X=-300:300:3,Y=-250:250:2,Z=0,B=-90:90:3,C=0:270:4", "test grid");
  const auto source = ConfigurationSource::grid(grid);
  ASSERT_EQ(source.size(), 72u);
  ASSERT_EQ(grid_count(grid), 72u);
  for (const std::size_t chunk : {std::size_t{1}, std::size_t{7}, std::size_t{72}, std::size_t{1000}}) {
    Gathered g;
    const StreamSummary s = gather(model, source, chunk, g);
    EXPECT_EQ(s.count, 72u);
    ASSERT_EQ(g.e.size(), 72u * 6) << chunk;
    // 72 is not a multiple of 7: the last chunk is short.
    EXPECT_EQ(g.first.size(), (72 + chunk - 1) / chunk) << chunk;
    for (std::size_t i = 0; i < 72; ++i) {
      const std::vector<double> q(g.q.begin() + static_cast<std::ptrdiff_t>(i * 5),
                                  g.q.begin() + static_cast<std::ptrdiff_t>(i * 5 + 5));
      const VolumetricError e = model.evaluate(q);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(g.e[i * 6 + c], e.translation[c], 1e-12) << i;
        EXPECT_NEAR(g.e[i * 6 + 3 + c], e.rotation[c], 1e-15) << i;
      }
    }
  }
}

// The grid kernel (each axis' transforms once per grid value, products of them) against the
// point-by-point kernel on the listed configurations: every example machine (polynomial,
// Fourier and table forms, 3 to 5 axes), whole and in stretches that start and end inside a row
// of the fastest axis, on 1 and 2 threads (the same bits).
TEST(ErrorStream, GridKernelEqualsPointByPointOnEveryExampleMachine) {
  for (const char* file : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "head-head-5axis.yaml", "rrttt-table-table.yaml"}) {
    const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + file);
    const ErrorModel model(m);
    EXPECT_TRUE(model.grid_structured()) << file;
    GridValues grid;
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
      const double lo = m.axes[k].travel ? m.axes[k].travel->min : -100.0;
      const double hi = m.axes[k].travel ? m.axes[k].travel->max : 100.0;
      const std::size_t count = 3 + (k * 2) % 7 + (k + 1 == m.axes.size() ? 10 : 0);  // the fastest axis longest
      std::vector<double> v;
      for (std::size_t j = 0; j < count; ++j)
        v.push_back(lo + (hi - lo) * (0.013 + 0.97 * static_cast<double>(j) / static_cast<double>(count - 1)));
      grid.push_back(v);
    }
    const std::size_t total = grid_count(grid), n = m.axes.size();
    std::vector<double> q(total * n), ref(total * 6);
    ConfigurationSource::grid(grid).fill_range(0, total, q.data(), nullptr);
    model.evaluate_batch(q, {}, ref, BatchOptions{1});
    std::vector<double> one(total * 6), two(total * 6);
    model.evaluate_grid(grid, 0, one, BatchOptions{1});
    model.evaluate_grid(grid, 0, two, BatchOptions{2});
    EXPECT_EQ(one, two) << file;
    double worst_t = 0, worst_r = 0;
    for (std::size_t i = 0; i < total; ++i)
      for (int c = 0; c < 3; ++c) {
        worst_t = std::max(worst_t, std::abs(one[i * 6 + c] - ref[i * 6 + c]));
        worst_r = std::max(worst_r, std::abs(one[i * 6 + 3 + c] - ref[i * 6 + 3 + c]));
      }
    // 1e-12 mm; on the gantry (X 3 m, head 1.2 m above the table) 2e-12 mm: a rigid-body product
    // of 2 m lever arms rounds by about 4e-13 mm per factor in either kernel (docs/conventions.md:
    // about 1e-13 mm at 1 m), and the two associate the factors differently (measured 1.08e-12).
    const bool gantry = std::string(file) == "head-head-5axis.yaml";
    EXPECT_LE(worst_t, gantry ? 2e-12 : 1e-12) << file;
    EXPECT_LE(worst_r, 1e-15) << file;
    // Stretches: the same numbers as the whole.
    for (std::size_t first = 0; first < total;) {
      const std::size_t len = std::min<std::size_t>(total - first, 37);
      std::vector<double> part(len * 6);
      model.evaluate_grid(grid, first, part, BatchOptions{1});
      for (std::size_t i = 0; i < len * 6; ++i) ASSERT_EQ(part[i], one[first * 6 + i]) << file << " at " << first;
      first += len;
    }
    // fill_range gives the configurations fill does.
    std::vector<double> row(n);
    for (std::size_t i : {std::size_t{0}, total / 3, total - 1}) {
      ConfigurationSource::grid(grid).fill(i, row.data(), nullptr);
      for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(row[k], q[i * n + k]);
    }
  }
  const Machine m = hu40t();
  std::vector<double> out(12);
  EXPECT_THROW(ErrorModel(m).evaluate_grid(GridValues{{0.0}, {0.0}}, 0, out), ModelError);
  EXPECT_THROW(ErrorModel(m).evaluate_grid(GridValues(5, std::vector<double>{0.0}), 0, out), ModelError);
}

TEST(ErrorStream, GridIndexLastAxisFastest) {
  const Machine m = hu40t();
  const std::size_t n = m.axes.size();
  const char first = m.axes.front().letter, last = m.axes.back().letter;
  const GridValues grid = parse_grid(m, fmt::format("{}=0:1:2,{}=0:20:3", first, last), "test grid");
  const auto source = ConfigurationSource::grid(grid);
  ASSERT_EQ(source.size(), 6u);
  const double f0 = joint_unit_factor(m.axes.front()), f1 = joint_unit_factor(m.axes.back());
  const double want_first[6] = {0, 0, 0, 1, 1, 1}, want_last[6] = {0, 10, 20, 0, 10, 20};
  std::vector<double> q(n);
  for (std::size_t i = 0; i < 6; ++i) {
    source.fill(i, q.data(), nullptr);
    EXPECT_NEAR(q.front(), want_first[i] * f0, 1e-15) << i;
    EXPECT_NEAR(q.back(), want_last[i] * f1, 1e-12) << i;
    for (std::size_t k = 1; k + 1 < n; ++k) EXPECT_EQ(q[k], 0.0) << i;
  }
}

TEST(ErrorStream, ListKeepsDirectionsAndTracksTheLargestErrors) {
  const Machine m = hu40t();
  const ErrorModel model(m);
  ConfigurationList list;
  list.axes = m.axes.size();
  const std::vector<std::string> rows = {"X=0", "X=300,Y=250,Z=300,B=90,C=270", "X=-300,Y=-250,B=-90", "X=100"};
  for (const auto& r : rows) {
    const auto q = parse_joint_values(m, r, "test");
    list.q.insert(list.q.end(), q.begin(), q.end());
    for (std::size_t k = 0; k < q.size(); ++k) list.dir.push_back(k % 2 ? 1 : -1);
  }
  Gathered g;
  const StreamSummary s = gather(model, ConfigurationSource::list(list), 3, g);
  EXPECT_EQ(g.dir, list.dir);
  double bt = -1, br = -1;
  std::size_t it = 0, ir = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::span<const double> q(&list.q[i * list.axes], list.axes);
    const std::span<const std::int8_t> d(&list.dir[i * list.axes], list.axes);
    const VolumetricError e = model.evaluate(q, d);
    if (e.translation.norm() > bt) bt = e.translation.norm(), it = i;
    if (e.rotation.norm() > br) br = e.rotation.norm(), ir = i;
  }
  EXPECT_NEAR(s.max_translation.value, bt, 1e-12);
  EXPECT_NEAR(s.max_rotation.value, br, 1e-15);
  EXPECT_EQ(s.max_translation.at, std::vector<double>(&list.q[it * list.axes], &list.q[it * list.axes] + list.axes));
  EXPECT_EQ(s.max_rotation.at, std::vector<double>(&list.q[ir * list.axes], &list.q[ir * list.axes] + list.axes));
}

TEST(ErrorStream, EmptySourceGivesZeroAndNoConfiguration) {
  const Machine m = hu40t();
  ConfigurationList list;
  list.axes = m.axes.size();
  bool called = false;
  const StreamSummary s =
      evaluate_stream(ErrorModel(m), ConfigurationSource::list(list), [&](const ErrorChunk&) { called = true; });
  EXPECT_FALSE(called);
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.max_translation.value, 0.0);
  EXPECT_TRUE(s.max_translation.at.empty());
}

TEST(ErrorStream, NonFiniteErrorNamesItsConfiguration) {
  Machine m = hu40t();
  m.set_parameter("EXX.3", 1e306);  // overflows to infinity at |X| >= 100 mm, finite at 0
  const ErrorModel model(m);
  ConfigurationList list;
  list.axes = m.axes.size();
  for (const char* r : {"X=0", "X=0,Y=5", "X=300", "X=0"}) {
    const auto q = parse_joint_values(m, r, "test");
    list.q.insert(list.q.end(), q.begin(), q.end());
  }
  std::size_t seen = 0;
  StreamOptions o;
  o.chunk = 2;
  try {
    evaluate_stream(
        model, ConfigurationSource::list(list), [&](const ErrorChunk& c) { seen += c.size(); }, o);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite error at configuration 3 of 4"), std::string::npos) << e.what();
  }
  EXPECT_EQ(seen, 2u);  // the chunk with the bad configuration never reached the sink
}

TEST(ErrorStream, GridChecksCountAndTravels) {
  const Machine m = hu40t();
  const GridValues big = parse_grid(m, "X=-300:300:1000,Y=-250:250:1000", "test grid");
  EXPECT_THROW(check_grid(m, big, "grid", true, 999'999), InputError);
  EXPECT_NO_THROW(check_grid(m, big, "grid", true, 1'000'000));
  const GridValues outside = parse_grid(m, "X=0:5000:3", "test grid");
  try {
    check_grid(m, outside, "the grid", true, 1000);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "the grid");
    EXPECT_NE(std::string(e.what()).find("outside the travel"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(check_grid(m, outside, "the grid", false, 1000));
}

}  // namespace
}  // namespace mtcal
