// The streamed volumetric study (bounded memory) against the in-memory study of the same map and
// against a comparison of every pair: the same numbers, bit for bit.
#include <gtest/gtest.h>

#include <string>

#include "brute_force.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::example;

namespace mt = ::mtcal::testing;

// A pair of the streamed study (indices into its held map) is the same as the in-memory one's
// (indices into the whole map): same value, same configurations, same error vectors.
void expect_same_pair(const ErrorMap& held, const PointPair& s, const ErrorMap& whole, const PointPair& w,
                      const std::string& what) {
  EXPECT_EQ(s.value, w.value) << what;
  for (auto [hi, wi] : {std::pair{s.i, w.i}, std::pair{s.j, w.j}}) {
    ASSERT_LT(hi, held.size()) << what;
    const auto a = held.configuration(hi), b = whole.configuration(wi);
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << what;
    EXPECT_EQ(held.error[hi], whole.error[wi]) << what;
  }
}

void expect_same_va(const ErrorMap& held, const VolumetricAccuracy& s, const ErrorMap& whole,
                    const VolumetricAccuracy& w, const std::string& what) {
  EXPECT_EQ(s.points, w.points) << what;
  EXPECT_EQ(s.pairs, w.pairs) << what;
  expect_same_pair(held, s.va, whole, w.va, what + " VA");
  for (std::size_t c = 0; c < 3; ++c) expect_same_pair(held, s.component[c], whole, w.component[c], what + " comp");
}

void expect_same_distribution(const Distribution& a, const Distribution& b, const std::string& what) {
  EXPECT_EQ(a.count, b.count) << what;
  EXPECT_EQ(a.mean, b.mean) << what;
  EXPECT_EQ(a.min, b.min) << what;
  EXPECT_EQ(a.max, b.max) << what;
  EXPECT_EQ(a.histogram.lo, b.histogram.lo) << what;
  EXPECT_EQ(a.histogram.width, b.histogram.width) << what;
  EXPECT_EQ(a.histogram.counts, b.histogram.counts) << what;
}

struct VolumetricStreamCase {
  std::string file, grid, box;
};

TEST(StreamedVolumetric, EqualsTheInMemoryStudyOnEveryExampleMachine) {
  for (const VolumetricStreamCase& c :
       {VolumetricStreamCase{"vmc-3axis.yaml", "X=-400:400:23,Y=-250:250:13,Z=-500:0:11", "X=0:400,Z=-300:0"},
        VolumetricStreamCase{"hu40t-wCBXfYZt.yaml", "X=-300:300:7,Y=-250:250:5,Z=-300:0:4,B=-90:90:5,C=0:360:9", "X=-100:300,C=0:180"},
        VolumetricStreamCase{"head-head-5axis.yaml", "X=0:1000:6,Y=0:800:5,Z=-400:0:4,A=-30:30:5,C=-90:90:7", "A=0:30"},
        VolumetricStreamCase{"rrttt-table-table.yaml", "X=-100:100:5,Y=-100:100:6,Z=-100:0:3,A=-30:30:5,C=0:90:4", "X=0:100"}}) {
    const Machine m = example(c.file);
    const ErrorModel model(m);
    const GridValues grid = parse_grid(m, c.grid, "test grid");
    const ErrorMap whole = grid_error_map(model, grid);
    VolumetricRequest request;
    request.box = parse_box(m, c.box, "test box");
    request.box_scan = 4;
    request.histogram = true;
    request.grouping = GroupingOptions{};
    const VolumetricStudy w = study_volumetric(m, whole, request);
    StreamOptions so;
    so.grid_kernel = false;  // the in-memory map's errors, configuration by configuration
    so.chunk = 1000;         // many chunks, and slices inside them
    const StreamedStudy s = study_volumetric(m, model, ConfigurationSource::grid(grid), request, so);
    const std::string what = c.file;
    EXPECT_EQ(s.study.map_points, whole.size());
    expect_same_va(s.map, s.study.va, whole, w.va, what);
    // And against the comparison of every pair.
    const auto bf = mt::brute_force_va(whole.error);
    EXPECT_EQ(s.study.va.va.value, bf.va) << what;
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(s.study.va.component[k].value, bf.component[k]) << what;
    // The critical pair's contributions.
    ASSERT_EQ(s.study.critical.items.size(), w.critical.items.size()) << what;
    for (std::size_t k = 0; k < w.critical.items.size(); ++k) {
      EXPECT_EQ(s.study.critical.items[k].error, w.critical.items[k].error) << what;
      EXPECT_EQ(s.study.critical.items[k].along, w.critical.items[k].along) << what;
    }
    // The box: its VA over the box's configurations.
    ASSERT_TRUE(s.study.box_va && s.study.box_map);
    expect_same_va(*s.study.box_map, *s.study.box_va, *w.box_map, *w.box_va, what + " box");
    ASSERT_EQ(s.study.scan.size(), w.scan.size());
    for (std::size_t k = 0; k < w.scan.size(); ++k) {
      EXPECT_EQ(s.study.scan[k].points, w.scan[k].points) << what;
      EXPECT_EQ(s.study.scan[k].lo, w.scan[k].lo) << what;
      EXPECT_EQ(s.study.scan[k].hi, w.scan[k].hi) << what;
      expect_same_pair(s.map, s.study.scan[k].va, whole, w.scan[k].va, what + " scan");
    }
    ASSERT_TRUE(s.study.pairs && s.study.magnitudes);
    expect_same_distribution(*s.study.pairs, *w.pairs, what + " pairs");
    expect_same_distribution(*s.study.magnitudes, *w.magnitudes, what + " magnitudes");
    ASSERT_TRUE(s.study.grouping);
    EXPECT_EQ(s.study.grouping->result.groups, w.grouping->result.groups);
    EXPECT_EQ(s.study.grouping->result.kept, w.grouping->result.kept);
    expect_same_pair(s.map, s.study.grouping->result.va, whole, w.grouping->result.va, what + " grouping");
    // The report's samples: every stride-th configuration, first in the held map.
    const std::size_t stride = (whole.size() + kMapSamples - 1) / kMapSamples;
    ASSERT_EQ(s.study.sample_points, (whole.size() + stride - 1) / stride);
    for (std::size_t k = 0; k < s.study.sample_points; ++k) EXPECT_EQ(s.map.error[k], whole.error[k * stride]);
    // Bounded memory: the exact search kept a small part of the map.
    EXPECT_LT(s.study.candidates, whole.size() / 10) << what;

    // With the grid kernel: the same to its rounding (1e-12 mm).
    so.grid_kernel = true;
    const StreamedStudy g = study_volumetric(m, model, ConfigurationSource::grid(grid), {}, so);
    EXPECT_NEAR(g.study.va.va.value, w.va.va.value, 2e-12) << what;
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_NEAR(g.study.va.component[k].value, w.va.component[k].value, 2e-12) << what;
  }
}

TEST(StreamedVolumetric, ListsWithDirectionsAndDegenerateMaps) {
  const Machine m = example("vmc-3axis.yaml");
  const ErrorModel model(m);
  ConfigurationList list;
  list.axes = 3;
  for (int i = 0; i < 500; ++i) {
    list.q.insert(list.q.end(), {-400.0 + 1.6 * i, 250.0 - i, -2.0 * (i % 250)});
    list.dir.insert(list.dir.end(), {static_cast<std::int8_t>(i % 2 ? 1 : -1), 1, static_cast<std::int8_t>(i % 3 - 1)});
  }
  const ErrorMap whole = error_map(model, list.q, list.dir);
  const VolumetricStudy w = study_volumetric(m, whole, {});
  StreamOptions small;
  small.chunk = 64;
  const StreamedStudy s = study_volumetric(m, model, ConfigurationSource::list(list), {}, small);
  expect_same_va(s.map, s.study.va, whole, w.va, "list");
  EXPECT_EQ(s.map.direction(s.study.va.va.i).size(), 3u);

  // An error-free machine: every vector is zero, VA 0 at the first configuration, as in memory.
  Machine perfect = m;
  perfect.clear_errors();
  const ErrorModel none(perfect);
  const GridValues grid = parse_grid(m, "X=-400:400:5,Y=0:100:3", "test grid");
  const ErrorMap zero = grid_error_map(none, grid);
  const VolumetricStudy wz = study_volumetric(perfect, zero, {});
  const StreamedStudy sz = study_volumetric(perfect, none, ConfigurationSource::grid(grid), {});
  expect_same_va(sz.map, sz.study.va, zero, wz.va, "zero");
  // One configuration.
  const GridValues one = parse_grid(m, "X=10", "test grid");
  const ErrorMap single = grid_error_map(model, one);
  StreamOptions point;
  point.grid_kernel = false;
  const StreamedStudy s1 = study_volumetric(m, model, ConfigurationSource::grid(one), {}, point);
  expect_same_va(s1.map, s1.study.va, single, study_volumetric(m, single, {}).va, "one");
}

TEST(StreamedVolumetric, ContributionsAndCorrectionSequenceEqualTheInMemoryOnes) {
  const Machine m = example("vmc-3axis.yaml");
  const GridValues grid = parse_grid(m, "X=-400:400:9,Y=-250:250:7,Z=-500:0:5", "test grid");
  const ErrorMap whole = grid_error_map(ErrorModel(m), grid);
  const ContributionStudy w = critical_pair_contributions(m, whole, true, 0, 0.004);
  StreamOptions point;
  point.grid_kernel = false;
  const ContributionStudy s = critical_pair_contributions(m, ConfigurationSource::grid(grid), true, point, 0.004);
  EXPECT_EQ(s.va->va.value, w.va->va.value);
  EXPECT_EQ(s.a, w.a);
  EXPECT_EQ(s.b, w.b);
  ASSERT_EQ(s.what_if.size(), w.what_if.size());
  for (std::size_t k = 0; k < w.what_if.size(); ++k) {
    EXPECT_EQ(s.what_if[k].error, w.what_if[k].error);
    EXPECT_EQ(s.what_if[k].va, w.what_if[k].va);
    EXPECT_EQ(s.what_if[k].from, w.what_if[k].from);
    EXPECT_EQ(s.what_if[k].to, w.what_if[k].to);
    EXPECT_EQ(s.what_if[k].disagrees, w.what_if[k].disagrees);
    EXPECT_EQ(s.what_if[k].cancelled.size(), w.what_if[k].cancelled.size());
  }
  ASSERT_TRUE(s.sequence && w.sequence);
  ASSERT_EQ(s.sequence->steps.size(), w.sequence->steps.size());
  for (std::size_t k = 0; k < w.sequence->steps.size(); ++k) {
    EXPECT_EQ(s.sequence->steps[k].error, w.sequence->steps[k].error);
    EXPECT_EQ(s.sequence->steps[k].va, w.sequence->steps[k].va);
  }
  EXPECT_EQ(s.sequence->reached, w.sequence->reached);
}

TEST(StreamedVolumetric, RemovalsOnAMapTooLargeToHoldEqualTheInMemoryOnes) {
  // 68,921 configurations: above the size the streamed removals hold in memory, so every removal
  // goes through the two streamed passes.
  const Machine m = example("vmc-3axis.yaml");
  const GridValues grid = parse_grid(m, "X=-400:400:41,Y=-250:250:41,Z=-500:0:41", "test grid");
  const ErrorMap whole = grid_error_map(ErrorModel(m), grid);
  const ContributionStudy w = critical_pair_contributions(m, whole, true);
  StreamOptions point;
  point.grid_kernel = false;
  point.chunk = 10000;
  const ContributionStudy s = critical_pair_contributions(m, ConfigurationSource::grid(grid), true, point);
  EXPECT_EQ(s.va->va.value, w.va->va.value);
  EXPECT_EQ(s.a, w.a);
  EXPECT_EQ(s.b, w.b);
  ASSERT_EQ(s.what_if.size(), w.what_if.size());
  for (std::size_t k = 0; k < w.what_if.size(); ++k) {
    EXPECT_EQ(s.what_if[k].error, w.what_if[k].error);
    EXPECT_EQ(s.what_if[k].va, w.what_if[k].va);
    EXPECT_EQ(s.what_if[k].from, w.what_if[k].from);
    EXPECT_EQ(s.what_if[k].to, w.what_if[k].to);
  }
}

}  // namespace
}  // namespace mtcal
