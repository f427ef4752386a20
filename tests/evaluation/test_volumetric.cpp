// Volumetric accuracy against exhaustive comparison of every pair, hand cases and degenerate sets.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "brute_force.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"

namespace mtcal {
namespace {

namespace mt = ::mtcal::testing;

std::vector<Vec3> random_set(std::size_t n, int kind, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> e(n);
  for (auto& v : e) {
    switch (kind) {
      case 0: v = Vec3(u(rng), u(rng), u(rng)) * 0.02; break;                  // cube, mm
      case 1: v = Vec3(g(rng) * 0.01, g(rng) * 0.003, g(rng) * 0.001); break;  // flat Gaussian
      case 2: v = Vec3(g(rng), g(rng), g(rng)).normalized() * 0.05; break;     // sphere shell: hardest
      default: v = Vec3(std::round(u(rng) * 4), std::round(u(rng) * 4), std::round(u(rng) * 4)) * 1e-3;  // ties
    }
  }
  return e;
}

void expect_same_as_brute_force(const std::vector<Vec3>& e, const std::string& what) {
  const auto bf = mt::brute_force_va(e);
  const auto r = volumetric_accuracy(e);
  EXPECT_EQ(r.va.value, bf.va) << what;
  // The tree search alone, without its starting pair, must find the same value.
  const auto r0 = volumetric_accuracy(e, {.initial_bound = false});
  EXPECT_EQ(r0.va.value, bf.va) << what << " (search without the initial bound)";
  if (e.size() >= 2) {
    EXPECT_EQ((e[r0.va.i] - e[r0.va.j]).norm(), r0.va.value) << what;
  }
  EXPECT_EQ(r.points, e.size());
  EXPECT_EQ(r.pairs, 0.5 * static_cast<double>(e.size()) * static_cast<double>(e.size() - 1));
  if (e.size() >= 2) {
    EXPECT_LT(r.va.i, r.va.j) << what;
    EXPECT_EQ((e[r.va.i] - e[r.va.j]).norm(), r.va.value) << what;
  }
  for (int c = 0; c < 3; ++c) {
    const auto& p = r.component[static_cast<std::size_t>(c)];
    EXPECT_EQ(p.value, bf.component[static_cast<std::size_t>(c)]) << what << " component " << c;
    EXPECT_EQ(e[p.j][c] - e[p.i][c], p.value) << what << " component " << c;
  }
}

TEST(VolumetricAccuracy, EqualsBruteForceOnRandomSets) {
  for (int kind = 0; kind < 4; ++kind)
    for (std::size_t n : {2u, 3u, 7u, 25u, 100u, 1000u, 4000u})
      expect_same_as_brute_force(random_set(n, kind, 17 * n + kind),
                                 "kind " + std::to_string(kind) + " n " + std::to_string(n));
}

TEST(VolumetricAccuracy, EqualsBruteForceOnTenThousandPoints) {
  for (int kind : {0, 2})
    expect_same_as_brute_force(random_set(10000, kind, 99), "n 10000 kind " + std::to_string(kind));
}

TEST(VolumetricAccuracy, EqualsBruteForceOnExampleErrorMaps) {
  // Structured sets: the error maps of the examples over 21 x 21 x 21 = 9261 points (Fletcher's grid).
  const Machine m3 = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  const ErrorMap map3 =
      grid_error_map(ErrorModel(m3), parse_grid(m3, "X=-400:400:21,Y=-250:250:21,Z=-500:0:21", "test grid"));
  ASSERT_EQ(map3.size(), 9261u);
  expect_same_as_brute_force(map3.error, "vmc-3axis 21^3");
  const Machine m5 = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
  const ErrorMap map5 =
      grid_error_map(ErrorModel(m5),
                     parse_grid(m5, "X=-300:300:9,Y=0:500:9,Z=-400:0:9,B=0:90:3,C=0:270:4", "test grid"));
  expect_same_as_brute_force(map5.error, "hu40t with rotary axes");
  // A machine with only squareness errors maps the grid affinely: many collinear and coplanar vectors.
  Machine sq = m3;
  sq.keep_only({"EC0Y", "EB0Z", "EA0Z"});
  const ErrorMap mapsq =
      grid_error_map(ErrorModel(sq), parse_grid(sq, "X=-400:400:11,Y=-250:250:11,Z=-500:0:11", "test grid"));
  expect_same_as_brute_force(mapsq.error, "squareness only");
}

TEST(VolumetricAccuracy, SearchBeatsTheStartingPairWhereItMust) {
  // On a sphere shell the extreme-point start misses the diameter: there the candidate filter and
  // the tree search must find the rest, to the same value as every pair compared.
  int improved = 0;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const auto e = random_set(100, 2, 1000 + seed);
    const auto r = volumetric_accuracy(e);
    EXPECT_LE(r.initial_bound, r.va.value);
    improved += r.initial_bound < r.va.value;
    EXPECT_EQ(r.va.value, mt::brute_force_va(e).va) << seed;
  }
  EXPECT_GE(improved, 10);
}

TEST(VolumetricAccuracy, DegenerateSets) {
  EXPECT_EQ(volumetric_accuracy(std::vector<Vec3>{}).va.value, 0.0);
  EXPECT_EQ(volumetric_accuracy(std::vector<Vec3>{}).pairs, 0.0);
  const std::vector<Vec3> one{Vec3(1, 2, 3)};
  EXPECT_EQ(volumetric_accuracy(one).va.value, 0.0);
  EXPECT_EQ(volumetric_accuracy(one).pairs, 0.0);
  // All equal (many): zero, and no pair is searched beyond the first bound.
  const std::vector<Vec3> same(5000, Vec3(0.001, -0.002, 0.003));
  const auto rs = volumetric_accuracy(same);
  EXPECT_EQ(rs.va.value, 0.0);
  EXPECT_EQ(rs.component[0].value, 0.0);
  EXPECT_LT(rs.distance_evaluations, 100000u);
  // Collinear: the ends of the segment. Hand value: points t (1, 2, 2) for t in [-3, 5] -> 8 * 3.
  std::vector<Vec3> line;
  for (int t = -3; t <= 5; ++t) line.push_back(Vec3(1, 2, 2) * t);
  const auto rl = volumetric_accuracy(line);
  EXPECT_DOUBLE_EQ(rl.va.value, 24.0);
  EXPECT_EQ(rl.va.i, 0u);
  EXPECT_EQ(rl.va.j, 8u);
  EXPECT_DOUBLE_EQ(rl.component[0].value, 8.0);
  EXPECT_DOUBLE_EQ(rl.component[2].value, 16.0);
  expect_same_as_brute_force(line, "collinear");
  // Coplanar: a 30 x 30 grid in the plane x + y + z = 0; diameter between opposite corners.
  std::vector<Vec3> plane;
  const Vec3 a = Vec3(1, -1, 0) / std::sqrt(2.0), b = Vec3(1, 1, -2) / std::sqrt(6.0);
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) plane.push_back(a * i + b * j);
  EXPECT_NEAR(volumetric_accuracy(plane).va.value, std::hypot(29.0, 29.0), 1e-12);
  expect_same_as_brute_force(plane, "coplanar");
  // Two points, and duplicates of them.
  std::vector<Vec3> two{Vec3(0, 0, 0), Vec3(3, 4, 0), Vec3(0, 0, 0), Vec3(3, 4, 0)};
  EXPECT_EQ(volumetric_accuracy(two).va.value, 5.0);
}

TEST(VolumetricAccuracy, SearchIsFarBelowAllPairs) {
  // The work on a real map: a 41^3 grid has 2.3e9 pairs; the search must compute a tiny part.
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  const ErrorMap map =
      grid_error_map(ErrorModel(m), parse_grid(m, "X=-400:400:41,Y=-250:250:41,Z=-500:0:41", "test grid"));
  const auto r = volumetric_accuracy(map.error);
  EXPECT_LT(static_cast<double>(r.distance_evaluations), 1e-3 * r.pairs);
}

TEST(ErrorMap, GridMatchesSingleEvaluationsAndOrder) {
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
  const ErrorModel model(m);
  const auto values = parse_grid(m, "X=-100:100:3,Z=-50:0:2,C=0:90:2", "test grid");
  const ErrorMap map = grid_error_map(model, values);
  ASSERT_EQ(map.size(), 12u);
  // The last axis of the chain (wCBXfYZt: Z) varies fastest, then Y, X, B, C.
  const auto iz = *m.axis_index('Z'), ic = *m.axis_index('C');
  EXPECT_EQ(map.configuration(0)[iz], -50.0);
  EXPECT_EQ(map.configuration(1)[iz], 0.0);
  EXPECT_EQ(map.configuration(0)[ic], 0.0);
  EXPECT_NEAR(map.configuration(6)[ic], M_PI / 2, 1e-15);
  for (std::size_t i = 0; i < map.size(); ++i) {
    const auto q = map.configuration(i);
    const VolumetricError e = model.evaluate(std::vector<double>(q.begin(), q.end()));
    EXPECT_LT((e.translation - map.error[i]).norm(), 1e-12);
  }
  // sub_map keeps exactly the points inside the box.
  std::vector<double> lo(m.axes.size(), -1e9), hi(m.axes.size(), 1e9);
  lo[*m.axis_index('X')] = 0;
  EXPECT_EQ(sub_map(map, lo, hi).size(), 8u);
  EXPECT_THROW(error_map(model, std::vector<double>(7, 0.0)), ModelError);
}

TEST(FletcherGrouping, HandCase) {
  // (1,0,0) and (0.5,0,0) share a direction: the smaller is below 0.9 of the larger and goes.
  // (0,1,0) is its own group. (0.95,0.01,0) joins the first group (|du| sums to ~0.011 < 0.1) and stays.
  const std::vector<Vec3> e{Vec3(1, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 1, 0), Vec3(0.95, 0.01, 0)};
  const auto r = fletcher_grouping(e, {0.1, 0.9});
  EXPECT_EQ(r.groups, 2u);
  EXPECT_EQ(r.kept, (std::vector<std::size_t>{0, 2, 3}));
  EXPECT_EQ(r.comparisons, 3.0);
  EXPECT_DOUBLE_EQ(r.va.value, std::sqrt(2.0));
  // Zero vectors have no direction: one group of their own.
  const std::vector<Vec3> z{Vec3::Zero(), Vec3(1, 0, 0), Vec3::Zero()};
  EXPECT_EQ(fletcher_grouping(z).groups, 2u);
  EXPECT_THROW(fletcher_grouping(e, {0.0, 0.9}), InputError);
  EXPECT_THROW(fletcher_grouping(e, {0.1, 1.5}), InputError);
  EXPECT_THROW(fletcher_grouping(e, {NAN, 0.9}), InputError);
}

TEST(FletcherGrouping, MatchesLinearScanAndStaysCloseToExact) {
  // The hashed search must give the groups of the plain rule (first group, in creation order,
  // within the tolerance of the running mean), checked by a linear scan written here.
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  const ErrorMap map =
      grid_error_map(ErrorModel(m), parse_grid(m, "X=-400:400:21,Y=-250:250:21,Z=-500:0:21", "test grid"));
  const double exact = volumetric_accuracy(map.error).va.value;
  std::size_t previous_kept = map.size() + 1;
  for (double tol : {0.05, 0.1, 0.2}) {
    std::vector<Vec3> sum;
    std::vector<double> cnt, largest;
    std::vector<std::size_t> member;
    for (const Vec3& v : map.error) {
      const Vec3 u = v.normalized();
      std::size_t g = 0;
      while (g < sum.size() && (u - sum[g] / cnt[g]).cwiseAbs().sum() > tol) ++g;
      if (g == sum.size()) sum.push_back(Vec3::Zero()), cnt.push_back(0), largest.push_back(0);
      sum[g] += u, cnt[g] += 1, largest[g] = std::max(largest[g], v.norm());
      member.push_back(g);
    }
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < map.size(); ++i)
      if (map.error[i].norm() >= 0.9 * largest[member[i]]) kept.push_back(i);
    const auto r = fletcher_grouping(map.error, {tol, 0.9});
    EXPECT_EQ(r.groups, sum.size()) << tol;
    EXPECT_EQ(r.kept, kept) << tol;
    EXPECT_LE(r.va.value, exact);
    EXPECT_GE(r.va.value, 0.95 * exact) << "tolerance " << tol;
    EXPECT_LT(r.kept.size(), map.size());
    EXPECT_LE(r.kept.size(), previous_kept);
    previous_kept = r.kept.size();
  }
}

TEST(PairDistribution, CountsEveryPairOnceAndMatchesBruteForce) {
  for (int kind : {0, 1, 3}) {
    const auto e = random_set(700, kind, 5 + kind);
    const auto d = mt::all_pair_distances(e);
    const std::size_t bins = 37;
    const auto r = pair_distribution(e, bins, 0.0, 2);
    ASSERT_EQ(r.count, d.size());
    ASSERT_EQ(r.histogram.total(), d.size());
    EXPECT_EQ(r.max, *std::max_element(d.begin(), d.end()));
    EXPECT_EQ(r.min, *std::min_element(d.begin(), d.end()));
    double sum = 0;
    for (double v : d) sum += v;
    EXPECT_NEAR(r.mean, sum / static_cast<double>(d.size()), 1e-12 * r.max);
    // Reference bins by division; a distance within 1e-9 of a bin edge may fall either side.
    std::vector<std::int64_t> ref(bins, 0);
    std::int64_t edge = 0;
    for (double v : d) {
      const double x = v / r.histogram.width;
      if (std::abs(x - std::round(x)) < 1e-9) ++edge;
      ++ref[std::min(bins - 1, static_cast<std::size_t>(std::floor(x)))];
    }
    std::int64_t off = 0;
    for (std::size_t b = 0; b < bins; ++b) off += std::abs(ref[b] - static_cast<std::int64_t>(r.histogram.counts[b]));
    EXPECT_LE(off, 2 * edge) << "kind " << kind;
    // Any thread count gives the same numbers.
    const auto r1 = pair_distribution(e, bins, 0.0, 1);
    EXPECT_EQ(r1.histogram.counts, r.histogram.counts);
    EXPECT_EQ(r1.mean, r.mean);
    // Percentiles within one bin of the exact order statistics.
    auto sorted = d;
    std::sort(sorted.begin(), sorted.end());
    for (double p : {0.5, 0.9, 0.99}) {
      const double exact = sorted[static_cast<std::size_t>(p * static_cast<double>(sorted.size() - 1))];
      EXPECT_NEAR(r.histogram.quantile(p), exact, r.histogram.width) << p;
    }
  }
}

TEST(PairDistribution, EdgeCases) {
  EXPECT_EQ(pair_distribution(std::vector<Vec3>{}, 10).count, 0u);
  EXPECT_EQ(pair_distribution(std::vector<Vec3>{Vec3(1, 1, 1)}, 10).histogram.total(), 0u);
  const auto same = pair_distribution(std::vector<Vec3>(50, Vec3(1, 1, 1)), 10);
  EXPECT_EQ(same.histogram.counts[0], 50u * 49u / 2u);
  EXPECT_EQ(same.max, 0.0);
  const auto e = random_set(50, 0, 1);
  EXPECT_THROW(pair_distribution(e, 0), InputError);
  EXPECT_THROW(pair_distribution(e, 10, 1e-9), InputError);  // below the VA
  // A wider range puts everything in the lower bins.
  const auto wide = pair_distribution(e, 10, 1.0);
  EXPECT_EQ(wide.histogram.counts[0], wide.count);
}

TEST(Histogram, QuantileHandCalculation) {
  Histogram h{0.0, 1.0, {2, 0, 6, 2}};  // 10 values
  EXPECT_EQ(h.total(), 10u);
  EXPECT_DOUBLE_EQ(h.quantile(0.1), 0.5);  // 1 of 2 in bin [0, 1)
  EXPECT_DOUBLE_EQ(h.quantile(0.5), 2.5);  // 3 of 6 in bin [2, 3)
  EXPECT_DOUBLE_EQ(h.quantile(1.0), 4.0);
  EXPECT_THROW(h.quantile(1.5), ModelError);
  const std::vector<double> v{1, 2, 3, 4, 10};
  const auto d = value_distribution(v, 9);
  EXPECT_EQ(d.min, 1.0);
  EXPECT_EQ(d.max, 10.0);
  EXPECT_DOUBLE_EQ(d.mean, 4.0);
  EXPECT_EQ(d.histogram.counts[0], 1u);
  EXPECT_EQ(d.histogram.counts[8], 1u);  // the maximum lands in the last bin
}

TEST(ReducedVolume, BoxVaGrowsWithTheBoxAndEqualsTheFullVaAtOne) {
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  const ErrorMap map =
      grid_error_map(ErrorModel(m), parse_grid(m, "X=-400:400:17,Y=-250:250:11,Z=-500:0:11", "test grid"));
  const double full = volumetric_accuracy(map.error).va.value;
  const std::vector<double> centre{0, 0, -250};
  const std::vector<double> fractions{0.1, 0.25, 0.5, 0.75, 1.0};
  const auto boxes = va_versus_box_size(map, centre, fractions);
  ASSERT_EQ(boxes.size(), 5u);
  EXPECT_EQ(boxes.back().va.value, full);
  EXPECT_EQ(boxes.back().points, map.size());
  for (std::size_t k = 1; k < boxes.size(); ++k) {
    EXPECT_GE(boxes[k].va.value, boxes[k - 1].va.value);
    EXPECT_GE(boxes[k].points, boxes[k - 1].points);
  }
  // Half the sides (Fletcher's 12 x 4 x 2 m -> 6 x 2 x 1 m): X in [-200, 200], the points of the grid inside.
  EXPECT_DOUBLE_EQ(boxes[2].lo[0], -200.0);
  EXPECT_DOUBLE_EQ(boxes[2].hi[2], -125.0);
  EXPECT_EQ(boxes[2].points, 9u * 5u * 5u);
  // The box's VA equals brute force over the points in it.
  std::vector<Vec3> inside;
  for (std::size_t i = 0; i < map.size(); ++i) {
    const auto q = map.configuration(i);
    bool in = true;
    for (std::size_t k = 0; k < 3; ++k) in = in && q[k] >= boxes[2].lo[k] && q[k] <= boxes[2].hi[k];
    if (in) inside.push_back(map.error[i]);
  }
  EXPECT_EQ(boxes[2].va.value, mt::brute_force_va(inside).va);
  const std::vector<double> bad{0.0};
  EXPECT_THROW(va_versus_box_size(map, centre, bad), InputError);
}

}  // namespace
}  // namespace mtcal
