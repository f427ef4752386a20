// Rotary-axis location errors from probed sphere centres (Cubas & Yeh 2022): exact recovery from
// simulated probing, the seed's triple counts, uncertainties that cover the truth, outlier
// rejection, and clear errors for degenerate or inconsistent input.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/probing/rotary_axis.hpp"
#include "mtcal/probing/rotary_probing.hpp"
#include "mtcal/probing/sphere_probing.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kDeg;

std::vector<double> steps(double from_deg, double to_deg, double step_deg) {
  std::vector<double> a;
  for (double d = from_deg; d <= to_deg + 1e-9; d += step_deg) a.push_back(d * kDeg);
  return a;
}

// Simulated probing of one axis of a table-table machine that has only that axis's location
// errors, and the sphere centres of the 5-point protocol.
struct RotaryAxisCase {
  Machine machine;
  std::vector<MeasuredCentre> centres;
};

RotaryAxisCase probe(char axis, const std::vector<std::pair<const char*, double>>& errors, const std::vector<double>& angles,
           double noise = 0.0, std::uint64_t seed = 1, double bias = 0.0, const char* topology = "wCAYXfZt") {
  Machine m = mtcal::testing::nominal_machine(topology);
  for (const auto& [name, v] : errors) m.set_parameter(name, v);
  ProbingSimulation sim;
  sim.axis = axis;
  sim.angles = angles;
  sim.sphere = Point3(150, -40, 80);
  sim.noise = noise;
  sim.trigger_bias = bias;
  sim.seed = seed;
  RotaryAxisCase c{m, {}};
  for (const auto& ix : simulate_probing(m, sim)) {
    const auto sc = sphere_centre(ix.contacts, sim.probing, "sim");
    EXPECT_TRUE(sc.five_point.has_value());
    c.centres.push_back({ix.angle, sc.centre()});
  }
  return c;
}

}  // namespace

TEST(RotaryAxis, LineConversionRoundTripsForEveryAxis) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (char letter : {'A', 'B', 'C'}) {
    NominalRotaryAxis axis = NominalRotaryAxis::by_letter(letter);
    axis.point = Point3(10, -20, 30);
    for (int i = 0; i < 20; ++i) {
      std::array<double, kRotaryQuantities> v{u(rng) * 100, u(rng) * 100, u(rng), u(rng), 123.0, 0.0};
      const auto [p, n] = line_from_location(axis, v);
      // Any point of the line gives the same errors.
      const auto back = location_from_line(axis, p + 37.0 * n, n, 123.0);
      for (std::size_t q = 0; q < 4; ++q) EXPECT_NEAR(back[q], v[q], q < 2 ? 1e-13 : 1e-15) << letter << q;
      const int k = axis.direction_axis;
      EXPECT_NEAR(back[5], std::atan2(std::hypot(n[(k + 1) % 3], n[(k + 2) % 3]), n[k]), 1e-15);
    }
  }
  EXPECT_EQ(rotary_quantity_names('A')[0], "EY0A");
  EXPECT_EQ(rotary_quantity_names('B')[3], "EC0B");
}

namespace {
// Noise-free probing of one axis recovers its location errors with both estimators.
void expect_recovered(char letter, const std::vector<std::pair<const char*, double>>& truth,
                      const std::vector<double>& angles, std::size_t expected_triples,
                      const char* topology = "wCAYXfZt") {
  const RotaryAxisCase c = probe(letter, truth, angles, 0.0, 1, 0.0, topology);
  ASSERT_EQ(c.centres.size(), angles.size());
  const auto axis = NominalRotaryAxis::from(c.machine.axis(letter));
  const auto tri = estimate_by_triples(axis, c.centres);
  const auto lsq = estimate_by_least_squares(axis, c.centres);
  EXPECT_EQ(tri.triples, expected_triples);
  for (std::size_t q = 0; q < 4; ++q) {
    EXPECT_NEAR(tri.value[q], truth[q].second, 1e-9) << truth[q].first;
    EXPECT_NEAR(lsq.value[q], truth[q].second, 1e-9) << truth[q].first;
  }
  // The angle between actual and nominal axis, from the two orientation errors.
  const double tilt = std::acos(std::cos(truth[2].second) * std::cos(truth[3].second));
  EXPECT_NEAR(tri.value[5], tilt, 1e-9);
  EXPECT_NEAR(lsq.value[5], tilt, 1e-9);
}
}  // namespace

TEST(RotaryAxis, NoiseFreeProbingRecoversTheCAxisLocationErrors) {
  // The seed's C protocol: 0..350 deg in 10 deg steps, C(36, 3) = 7,140 triples.
  expect_recovered('C', {{"EX0C", 0.012}, {"EY0C", -0.008}, {"EA0C", 25e-6}, {"EB0C", -40e-6}}, steps(0, 350, 10),
                   7140);
}

TEST(RotaryAxis, NoiseFreeProbingRecoversTheAAxisLocationErrors) {
  // The seed's A protocol: -90..30 deg in 10 deg steps, C(13, 3) = 286 triples.
  expect_recovered('A', {{"EY0A", -0.015}, {"EZ0A", 0.02}, {"EB0A", 30e-6}, {"EC0A", 15e-6}}, steps(-90, 30, 10), 286);
}

TEST(RotaryAxis, NoiseFreeProbingRecoversTheBAxisLocationErrors) {
  expect_recovered('B', {{"EX0B", 0.007}, {"EZ0B", -0.011}, {"EA0B", -20e-6}, {"EC0B", 35e-6}}, steps(-90, 90, 15), 286,
                   "wBfXYZt");
}

TEST(RotaryAxis, UncertaintiesCoverTheTruthWithNoise) {
  const std::vector<std::pair<const char*, double>> truth = {{"EX0C", 0.012},
                                                             {"EY0C", -0.008},
                                                             {"EA0C", 25e-6},
                                                             {"EB0C", -40e-6}};
  int inside_tri = 0, inside_lsq = 0, total = 0;
  std::array<double, 4> z2_tri{}, z2_lsq{};  // mean squared normalised error per quantity
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const RotaryAxisCase c = probe('C', truth, steps(0, 350, 10), 0.001, seed);
    const auto axis = NominalRotaryAxis::from(c.machine.axis('C'));
    const auto tri = estimate_by_triples(axis, c.centres);
    const auto lsq = estimate_by_least_squares(axis, c.centres);
    for (std::size_t q = 0; q < 4; ++q) {
      ++total;
      inside_tri += std::abs(tri.value[q] - truth[q].second) <= 3 * tri.uncertainty[q];
      inside_lsq += std::abs(lsq.value[q] - truth[q].second) <= 3 * lsq.uncertainty[q];
      z2_tri[q] += std::pow((tri.value[q] - truth[q].second) / tri.uncertainty[q], 2) / 20;
      z2_lsq[q] += std::pow((lsq.value[q] - truth[q].second) / lsq.uncertainty[q], 2) / 20;
      // And the uncertainties are of the right size for 1 um noise, not inflated.
      EXPECT_LT(lsq.uncertainty[q], q < 2 ? 2e-3 : 2e-5);
      EXPECT_LT(tri.uncertainty[q], q < 2 ? 2e-3 : 2e-5);
    }
  }
  // Calibrated, not merely covering: E[z^2] = 1; 20 trials leave a wide but informative window.
  for (std::size_t q = 0; q < 4; ++q) {
    EXPECT_GT(z2_tri[q], 0.4) << truth[q].first;
    EXPECT_LT(z2_tri[q], 1.8) << truth[q].first;
    EXPECT_GT(z2_lsq[q], 0.4) << truth[q].first;
    EXPECT_LT(z2_lsq[q], 1.8) << truth[q].first;
  }
  EXPECT_GE(inside_tri, total * 95 / 100) << inside_tri << " of " << total;
  EXPECT_GE(inside_lsq, total * 95 / 100) << inside_lsq << " of " << total;
}

TEST(RotaryAxis, TriplesGiveTheSameBitsWithAnyThreadCount) {
  const RotaryAxisCase c = probe('C', {{"EX0C", 0.01}}, steps(0, 350, 10), 0.001, 9);
  const auto axis = NominalRotaryAxis::from(c.machine.axis('C'));
  const auto a = estimate_by_triples(axis, c.centres, TriplesOptions{2.0, 40, 1});
  const auto b = estimate_by_triples(axis, c.centres, TriplesOptions{2.0, 40, 3});
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.uncertainty, b.uncertainty);
  EXPECT_EQ(a.kept, b.kept);
}

// The small-angle series in location_from_line against the library's atan2 / asin: the same
// quantities to 2 ulp (relative 5e-16), for angles on both sides of the 1e-3 rad switch.
TEST(RotaryAxis, LocationFromLineAnglesEqualTheLibraryFunctions) {
  const auto axis = NominalRotaryAxis::by_letter('C');
  for (double a : {0.0, 3e-9, -2e-6, 4.5e-5, -9.9e-4, 1.01e-3, -0.02, 0.3})
    for (double b : {0.0, -7e-8, 1.2e-5, -8e-4, 2e-3, -0.1}) {
      const Point3 n(std::cos(a) * std::sin(b), -std::sin(a), std::cos(a) * std::cos(b));
      const auto q = location_from_line(axis, Point3(0.1, -0.2, 0.0), n, 50.0);
      const Point3 u = n.normalized();
      const double ref[3] = {-std::asin(u.y()), std::atan2(u.x(), u.z()), std::atan2(std::hypot(u.x(), u.y()), u.z())};
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(q[static_cast<std::size_t>(2 + (k == 2 ? 3 : k))], ref[k], 5e-16 * std::abs(ref[k]))
            << a << " " << b << " quantity " << k;
    }
}

TEST(RotaryAxis, TriplesReportProgressOverBothPasses) {
  const RotaryAxisCase c = probe('C', {{"EX0C", 0.01}}, steps(0, 350, 10), 0.001, 9);
  const auto axis = NominalRotaryAxis::from(c.machine.axis('C'));
  std::vector<std::size_t> seen;
  TriplesOptions o{2.0, 40, 2};
  o.progress = [&](std::size_t done, std::size_t total) {
    seen.push_back(done);
    EXPECT_EQ(total, 128u);
  };
  const auto with = estimate_by_triples(axis, c.centres, o);
  ASSERT_EQ(seen.size(), 128u);
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], i + 1);
  EXPECT_EQ(with.value, estimate_by_triples(axis, c.centres, TriplesOptions{2.0, 40, 1}).value);
}

TEST(RotaryAxis, AnOutlierIsRejectedByTheSigmaRule) {
  const std::vector<std::pair<const char*, double>> truth = {{"EX0C", 0.01},
                                                             {"EY0C", 0.0},
                                                             {"EA0C", 0.0},
                                                             {"EB0C", 0.0}};
  RotaryAxisCase c = probe('C', truth, steps(0, 350, 10), 0.0005, 3);
  c.centres[7].centre += Point3(0.08, -0.05, 0.03);  // one bad centre (a chip on the sphere)
  const auto axis = NominalRotaryAxis::from(c.machine.axis('C'));
  const auto with = estimate_by_triples(axis, c.centres, TriplesOptions{2.0, 40, 0});
  const auto without = estimate_by_triples(axis, c.centres, TriplesOptions{0.0, 40, 0});
  // The rule always drops some tails; the triples through the bad centre are dropped far more
  // often than those through any other.
  ASSERT_EQ(with.rejected_share.size(), c.centres.size());
  for (std::size_t i = 0; i < c.centres.size(); ++i)
    if (i != 7) {
      EXPECT_GT(with.rejected_share[7], 3 * with.rejected_share[i]) << i;
    }
  EXPECT_EQ(without.kept[0], without.triples - without.degenerate);
  EXPECT_LT(std::abs(with.value[0] - 0.01), std::abs(without.value[0] - 0.01));
}

TEST(RotaryAxis, DegenerateCentresAreRefused) {
  const auto axis = NominalRotaryAxis::by_letter('C');
  EXPECT_THROW(estimate_by_triples(axis, {{0, Point3(1, 0, 0)}, {1, Point3(0, 1, 0)}}), InputError);
  const std::vector<MeasuredCentre> line = {{0, Point3(1, 0, 0)},
                                            {1, Point3(2, 0, 0)},
                                            {2, Point3(3, 0, 0)},
                                            {3, Point3(4, 0, 0)}};
  EXPECT_THROW(estimate_by_triples(axis, line), InputError);
  EXPECT_THROW(estimate_by_least_squares(axis, line), InputError);
  EXPECT_THROW(NominalRotaryAxis::by_letter('X'), ModelError);
}

TEST(SphereProbing, FivePointProtocolAndBias) {
  const Point3 centre(12, -7, 3);
  const double reach = 18.0;  // (30 + 6) / 2
  std::vector<ProbeContact> contacts;
  for (const Point3& a : five_point_approaches()) contacts.push_back({centre - reach * a, a});
  const auto sc = sphere_centre(contacts, {30, 6, 0.01}, "t");
  ASSERT_TRUE(sc.five_point.has_value());
  EXPECT_LE((*sc.five_point - centre).norm(), 1e-10);
  EXPECT_LE((sc.least_squares - centre).norm(), 1e-10);
  EXPECT_EQ(sc.subset_centres.size(), 4u);
  ASSERT_TRUE(sc.effective_radius.has_value());
  EXPECT_NEAR(*sc.effective_radius, reach, 1e-9);
  // Pre-travel of 2 um: the free fit sees the tip 2 um nearer the centre.
  for (auto& c : contacts) c.point += 0.002 * c.approach;
  EXPECT_NEAR(*sphere_centre(contacts, {30, 6, 0.01}, "t").effective_radius, reach - 0.002, 1e-9);
}

TEST(SphereProbing, ContactsNotOnTheSphereAreRefused) {
  std::vector<ProbeContact> contacts;
  for (const Point3& a : five_point_approaches()) contacts.push_back({Point3(0, 0, 0) - 18.0 * a, a});
  EXPECT_NO_THROW(sphere_centre(contacts, {30, 6, 0.01}, "t"));
  EXPECT_THROW(sphere_centre(contacts, {20, 6, 0.01}, "t"), InputError);  // wrong sphere
  try {  // too small a sphere for the contacts: said as such, not as degenerate contacts
    sphere_centre(contacts, {10, 6, 0.01}, "t");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not on a sphere of diameter 10"), std::string::npos) << e.what();
  }
  contacts[2].point += Point3(0.5, 0.5, 0);  // a stray contact
  EXPECT_THROW(sphere_centre(contacts, {30, 6, 0.01}, "t"), InputError);
  EXPECT_THROW(sphere_centre({contacts[0], contacts[1]}, {30, 6, 0.01}, "t"), InputError);
  EXPECT_THROW(sphere_centre(contacts, {0, 6, 0.01}, "t"), InputError);
}

TEST(SphereProbing, SimulationNeedsATableAxis) {
  const Machine head = mtcal::testing::nominal_machine("wXfYZCAt");
  ProbingSimulation sim;
  sim.axis = 'C';
  sim.angles = {0.0, 1.0};
  EXPECT_THROW(simulate_probing(head, sim), ModelError);
}

// Centres of a sphere turning about a line (point p, unit direction n), radius r, at the angles.
namespace {
std::vector<MeasuredCentre> circle_centres(const Point3& p, const Point3& n, double r, const std::vector<double>& deg) {
  const Point3 u = n.unitOrthogonal(), v = n.cross(u);
  std::vector<MeasuredCentre> out;
  for (double d : deg) out.push_back({d * kDeg, p + r * (std::cos(d * kDeg) * u + std::sin(d * kDeg) * v)});
  return out;
}
}  // namespace

TEST(RotaryAxis, AnglesATurnApartAreOnePositionForTheTriples) {
  // A C axis with EX0C = 10 um, EA0C = 20 urad, probed from -360 to +360 deg in 45 deg steps:
  // -360, 0 and 360 (and -180, 180) are the same positions; the seed's triples analysis used to
  // meet coincident centres. Merged, both estimators give the line exactly.
  const Point3 n = Point3(0, -std::sin(20e-6), std::cos(20e-6));
  std::vector<double> deg;
  for (double d = -360; d <= 360; d += 45) deg.push_back(d);
  IndexedCentres c;
  c.centres = circle_centres(Point3(0.010, 0, 0), n, 120, deg);
  const auto r = locate_rotary_axis(NominalRotaryAxis::by_letter('C'), c, {});
  EXPECT_EQ(r.centres.centres.size(), 8u);  // 17 angles, 8 positions
  ASSERT_FALSE(r.notes.empty());
  ASSERT_TRUE(r.triples && r.least_squares);
  EXPECT_EQ(r.triples->degenerate, 0u);
  for (const RotaryEstimate* e :
       {static_cast<const RotaryEstimate*>(&*r.triples), static_cast<const RotaryEstimate*>(&*r.least_squares)}) {
    EXPECT_NEAR(e->value[0], 0.010, 1e-9);  // EX0C
    EXPECT_NEAR(e->value[2], 20e-6, 1e-9);  // EA0C
  }
}

TEST(RotaryAxisLine, AnyDirectionIsMeasuredAndAGivenFrameBringsItHome) {
  // A rotary table seen by an instrument whose axes are turned 30 deg about x and 50 deg about z:
  // in the instrument's coordinates the C axis points nowhere near x, y or z.
  const Point3 p(5, -3, 2), n_machine = Point3(0, 0, 1);
  const InstrumentFrame frame = frame_from_angles(30 * kDeg, 0, 50 * kDeg, Point3(1, 2, 3));
  const Eigen::Matrix3d to_instrument = frame.rotation.transpose();
  std::vector<double> deg;
  for (double d = 0; d < 360; d += 30) deg.push_back(d);
  IndexedCentres c;
  for (const auto& m : circle_centres(p, n_machine, 100, deg))
    c.centres.push_back({m.angle, to_instrument * (m.centre - frame.translation)});
  // Without the frame: the line is measured in any direction, the location errors are not claimed.
  const auto raw = locate_rotary_axis(NominalRotaryAxis::by_letter('C'), c, {});
  EXPECT_FALSE(raw.located);
  EXPECT_FALSE(raw.least_squares || raw.triples);
  const Point3 expected = to_instrument * n_machine;
  EXPECT_NEAR(std::abs(raw.line.direction.dot(expected)), 1.0, 1e-12);
  EXPECT_NEAR(raw.line.radius, 100, 1e-9);
  EXPECT_NEAR(raw.line.tilt, std::acos(std::abs(expected.z())), 1e-9);
  // The line passes through the axis: its point is the foot of the origin on it.
  const Point3 on_line = to_instrument * (p - frame.translation);
  EXPECT_NEAR((raw.line.point - on_line).cross(raw.line.direction).norm(), 0, 1e-9);
  // With the frame: the machine's C axis, EX0C = 5, EY0C = -3, no tilt.
  apply_frame(c, frame);
  const auto r = locate_rotary_axis(NominalRotaryAxis::by_letter('C'), c, {});
  ASSERT_TRUE(r.located);
  EXPECT_NEAR(r.least_squares->value[0], 5, 1e-9);
  EXPECT_NEAR(r.least_squares->value[1], -3, 1e-9);
  EXPECT_NEAR(r.least_squares->value[5], 0, 1e-9);
  // An axis perpendicular to the nominal one (along x for C) is measured too.
  IndexedCentres side;
  side.centres = circle_centres(Point3(0, 1, 1), Point3(1, 0, 0), 50, deg);
  const auto s = locate_rotary_axis(NominalRotaryAxis::by_letter('C'), side, {});
  EXPECT_FALSE(s.located);
  EXPECT_NEAR(std::abs(s.line.direction.x()), 1.0, 1e-12);
  EXPECT_NEAR(s.line.tilt, std::numbers::pi / 2, 1e-9);
}

// rotary-axis --contacts from a controller's probe log (issue 31 item 3): the log holds the axis
// values at each trip. Contacts simulated on a machine with C's location errors, written as the axis
// values a controller would log (the linear axes that put the nominal tool point, rotary axes at
// zero, on the recorded point: solved here from the nominal chain's affine map), read back by
// contacts_from_log: the same points, approaches along the protocol's, the same centres.
TEST(RotaryAxis, ContactsFromAProbeLogAreTheSimulatedOnes) {
  Machine m = mtcal::testing::nominal_machine("wCAYXfZt");
  m.set_parameter("EX0C", 0.012);
  m.set_parameter("EA0C", 4e-5);
  ProbingSimulation sim;
  sim.axis = 'C';
  sim.angles = steps(-180, 150, 30);
  sim.sphere = Point3(150, -40, 80);
  const auto probed = simulate_probing(m, sim);
  const ErrorModel model(m);
  const std::size_t n = m.axes.size(), kc = *m.axis_index('C');
  std::vector<std::size_t> lin;
  for (std::size_t a = 0; a < n; ++a)
    if (m.axes[a].kind == AxisKind::Linear) lin.push_back(a);
  const std::vector<double> zero(n, 0.0);
  const Point3 p0 = model.nominal_pose(zero).t + m.workpiece.origin;
  Eigen::Matrix3d A;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> q = zero;
    q[lin[static_cast<std::size_t>(c)]] = 1.0;
    A.col(c) = model.nominal_pose(q).t + m.workpiece.origin - p0;
  }
  std::vector<LoggedAxisValues> log;
  std::vector<ProbeContact> expected;
  int line = 0;
  for (const auto& ix : probed)
    for (const auto& c : ix.contacts) {
      const Eigen::Vector3d x = A.fullPivLu().solve(c.point - p0);
      std::vector<double> q(n, 0.0);
      for (int k = 0; k < 3; ++k) q[lin[static_cast<std::size_t>(k)]] = x[k];
      q[kc] = ix.angle;
      log.push_back({q, ++line});
      expected.push_back(c);
    }
  const ContactSet set = contacts_from_log(m, 'C', log, "probe.txt");
  ASSERT_EQ(set.contacts.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_LT((set.contacts[i].contact.point - expected[i].point).norm(), 1e-9) << i;
    EXPECT_GT(set.contacts[i].contact.approach.dot(expected[i].approach), 0.9999) << i;
    EXPECT_EQ(set.contacts[i].line, static_cast<int>(i) + 1);
  }
  const IndexedCentres from_log = centres_from_contacts(set, sim.probing);
  EXPECT_EQ(from_log.method, "five-point");  // the approaches found are the protocol's
  ASSERT_EQ(from_log.centres.size(), probed.size());
  for (std::size_t i = 0; i < probed.size(); ++i) {
    const auto sc = sphere_centre(probed[i].contacts, sim.probing, "sim");
    EXPECT_LT((from_log.centres[i].centre - sc.centre()).norm(), 1e-9);
    EXPECT_NEAR(from_log.centres[i].angle, probed[i].angle, 1e-12);
  }
  // Bad logs: none, one without C, one without Y; an axis that is not rotary.
  EXPECT_THROW(contacts_from_log(m, 'C', {}, "probe.txt"), InputError);
  auto bad = log;
  bad[3].q[kc] = std::nan("");
  try {
    contacts_from_log(m, 'C', bad, "probe.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("probe.txt:4"), std::string::npos) << e.what();
  }
  bad = log;
  bad[6].q[*m.axis_index('Y')] = std::nan("");
  EXPECT_THROW(contacts_from_log(m, 'C', bad, "probe.txt"), InputError);
  EXPECT_THROW(contacts_from_log(m, 'X', log, "probe.txt"), ModelError);
  // A turns at line 9 (the RRTTT plan's logs turn A and C together: not a test of C alone).
  bad = log;
  bad[8].q[*m.axis_index('A')] = 0.5;
  try {
    contacts_from_log(m, 'C', bad, "probe.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("probe.txt:9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected A held at 0 deg"), std::string::npos) << e.what();
  }
}
