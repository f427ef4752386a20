// The probing program of a plan through mtcal's G-code reader and LinuxCNC's rs274, its probe logs
// read back into measurements that identify reads, and the log reader's bad inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>

#include <Eigen/LU>
#include <fmt/format.h>

#include "mtcal/identification/plan_study.hpp"
#include "mtcal/identification/planning.hpp"
#include "mtcal/identification/sphere_locate.hpp"
#include "mtcal/identification/error_draw.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/gcode/probe_program.hpp"
#include "mtcal/io/instruments/probe_log.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/gcode/rs274.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/kinematics/tool_point_coordinates.hpp"
#include "input_errors.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

namespace mtcal {
namespace {

using mtcal::testing::hu40t;
using mtcal::testing::kPlans;

// A small plan: the paper's first six ball probings and four facet touches of indexation 17.
ProbingPlan small_plan(const Machine& m) {
  ProbingPlan p = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  std::vector<ProbingRecord> keep(p.records.begin(), p.records.begin() + 6);
  for (const auto& r : p.records)
    if (p.features[r.feature].kind == ProbeFeature::Kind::Facet && r.indexation == 17) keep.push_back(r);
  p.records = keep;
  return plan_targets(m, p);
}

GcodeOptions xyzbc() {
  GcodeOptions o;
  o.axes = "XYZBC";
  return o;
}

using testing::error_message;

// LinuxCNC's log of the program's touches as a perfect machine would trip them: the expected
// contacts, plus noise; "%.6f" nine columns like LinuxCNC.
std::string log_of(const Machine& m, const std::vector<ProbeTouch>& touches, double noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::string s;
  for (const auto& t : touches) {
    std::array<double, 9> v{};
    const std::string letters = "XYZABCUVW";
    for (std::size_t c = 0; c < 9; ++c)
      if (const auto k = m.axis_index(letters[c]))
        v[c] = m.axes[*k].kind == AxisKind::Rotary ? t.expected[*k] * 180 / std::numbers::pi
                                                    : t.expected[*k] + noise * g(rng);
    s += fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", v[0], v[1], v[2], v[3], v[4],
                     v[5], v[6], v[7], v[8]);
  }
  return s;
}

TEST(ProbeProgram, TouchesSitOnTheBallAndTheFacet) {
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  const ProbeCycle c;
  const auto touches = probe_touches(m, p, c);
  ASSERT_EQ(touches.size(), 6u * 5 + 4);
  const double rho = (c.ball_diameter + c.tip_diameter) / 2;
  const std::size_t X = *m.axis_index('X'), Y = *m.axis_index('Y'), Z = *m.axis_index('Z');
  for (const auto& t : touches) {
    const auto& r = p.records[t.record];
    const Vec3 centre(r.q[X], r.q[Y], r.q[Z]), e(t.expected[X], t.expected[Y], t.expected[Z]),
        s(t.start[X], t.start[Y], t.start[Z]), f(t.end[X], t.end[Y], t.end[Z]);
    if (p.features[r.feature].kind == ProbeFeature::Kind::Ball) {
      EXPECT_NEAR((e - centre).norm(), rho, 1e-12);
      EXPECT_NEAR((s - centre).norm(), rho + c.approach, 1e-12);
      EXPECT_NEAR((f - centre).norm(), rho - c.overtravel, 1e-12);
    } else {
      // The facet (x = 200, normal +x) is probed along X towards -x: start 3 mm before, end 2 beyond.
      EXPECT_NEAR((e - centre).norm(), 0.0, 1e-12);
      EXPECT_NEAR(s.x() - e.x(), c.approach, 1e-9);
      EXPECT_NEAR(e.x() - f.x(), c.overtravel, 1e-9);
    }
  }
}

TEST(ProbeProgram, HeaderCommentKeepsOneParenthesisPair) {
  // The machine names of the examples hold parentheses; LinuxCNC refuses a '(' inside a comment
  // ("Nested comment found", met running the program in LinuxCNC, tests/linuxcnc/run-probe).
  const Machine m = hu40t();
  ProbeProgramOptions o;
  o.header = "machine " + m.name + " (twice (nested)): 3 poses";
  const std::string prog = probe_program(m, small_plan(m), ProbeCycle{}, o);
  EXPECT_NE(prog.find("(machine "), std::string::npos);
  EXPECT_NE(prog.find("[twice [nested]]: 3 poses)"), std::string::npos) << prog.substr(0, 400);
  std::istringstream lines(prog);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_LE(std::count(line.begin(), line.end(), '('), 1) << line;
    EXPECT_LE(std::count(line.begin(), line.end(), ')'), 1) << line;
  }
}

TEST(ProbeProgram, MtcalsReaderFollowsTheProgram) {
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  const ProbeCycle c;
  const auto touches = probe_touches(m, p, c);
  for (const auto dialect : {ProbeDialect::LinuxCNC, ProbeDialect::Iso}) {
    ProbeProgramOptions o;
    o.dialect = dialect;
    const std::string prog = probe_program(m, p, c, o);
    const char* word = dialect == ProbeDialect::LinuxCNC ? "G38.2" : "G31";
    // mtcal's reader simulates no probing (the path depends on the trip): it says so at the first
    // probing move (LinuxCNC) ...
    if (dialect == ProbeDialect::LinuxCNC) {
      const std::string msg = error_message([&] { parse_gcode(prog, "probe.ngc", xyzbc()); });
      EXPECT_NE(msg.find("G38.2 probing"), std::string::npos) << msg;
    }
    // ... so each probing move is read as the straight feed to its end (the probe not tripping):
    // every such move ends at its touch's end, at its record's indexation.
    const std::string as_feed = std::regex_replace(prog, std::regex(dialect == ProbeDialect::LinuxCNC ? "G38\\.2" : "G31"), "G1");
    const GcodeProgram g = parse_gcode(as_feed, "probe.ngc", xyzbc());
    std::size_t i = 0;
    std::istringstream lines(prog);
    std::string line;
    std::vector<int> probe_lines;
    for (int n = 1; std::getline(lines, line); ++n)
      if (line.rfind(word, 0) == 0) probe_lines.push_back(n);
    ASSERT_EQ(probe_lines.size(), touches.size());
    for (const auto& mv : g.moves) {
      if (i < probe_lines.size() && mv.line == probe_lines[i]) {
        const auto& t = touches[i];
        for (char a : {'X', 'Y', 'Z'}) EXPECT_NEAR(mv.end[std::string("XYZABC").find(a)], t.end[*m.axis_index(a)], 1e-6);
        for (char a : {'B', 'C'})
          EXPECT_NEAR(mv.end[std::string("XYZABC").find(a)], t.end[*m.axis_index(a)] * 180 / std::numbers::pi, 1e-6);
        ++i;
      }
    }
    EXPECT_EQ(i, touches.size());
  }
}

// The program's time from its text: G0 at the rapid of each axis and the rotary axes at the
// indexing speed (the largest time sets it; a run of rotary blocks, one indexation, then the
// settle), G1 and the probing move at their F along the X Y Z path, a probing move stopping
// `approach` along its way (where a machine without errors trips). From the block before the first
// G1 on (the first record's G0 down): the moves before it start from wherever the machine is.
TimeEstimate time_of_program(const std::string& prog, const char* probe_word, const TimingOptions& o, double approach) {
  struct Block {
    std::string code;
    std::map<char, double> to;
    double f = 0;
  };
  std::vector<Block> blocks;
  std::map<char, double> at;
  std::istringstream lines(prog);
  const std::regex word(R"(([XYZBCF])(-?[0-9.]+))");
  for (std::string line; std::getline(lines, line);) {
    const std::string code = line.substr(0, line.find(' '));
    if (code != "G0" && code != "G1" && code != probe_word) continue;
    Block b{code, at, 0};
    for (auto it = std::sregex_iterator(line.begin(), line.end(), word); it != std::sregex_iterator(); ++it) {
      const char a = (*it)[1].str()[0];
      (a == 'F' ? b.f : b.to[a]) = std::stod((*it)[2]);
    }
    at = b.to;
    blocks.push_back(b);
  }
  std::size_t first = 0;
  while (first < blocks.size() && blocks[first].code != "G1") ++first;
  EXPECT_GT(first, 0u);
  EXPECT_EQ(blocks[first - 1].code, "G0");
  auto rot_of = [&](std::size_t i) {
    double rot = 0;
    for (char a : {'B', 'C'}) rot = std::max(rot, std::abs(blocks[i].to[a] - blocks[i - 1].to[a]));
    return rot;
  };
  TimeEstimate t;
  for (std::size_t i = first - 1; i < blocks.size(); ++i) {
    auto& to = blocks[i].to;
    const auto& from = blocks[i - 1].to;
    double lin = 0, largest = 0;
    for (char a : {'X', 'Y', 'Z'}) {
      const double d = to[a] - from.at(a);
      lin += d * d;
      largest = std::max(largest, std::abs(d));
    }
    lin = std::sqrt(lin);
    const double f = blocks[i].f, rot = rot_of(i);
    if (blocks[i].code == probe_word) {
      t.probing += approach / (f / 60);
      for (char a : {'X', 'Y', 'Z'}) to[a] = from.at(a) + (to[a] - from.at(a)) * approach / lin;
      ++t.touches;
    } else if (blocks[i].code == "G1") {
      t.moves += lin / (f / 60);  // the retracts too (estimate_time counts them with the probing)
    } else if (rot > 0) {
      t.indexing += std::max(largest / (o.rapid / 60), rot / (o.rotary_speed / 60));
      if (i + 1 == blocks.size() || blocks[i + 1].code != "G0" || rot_of(i + 1) == 0) t.indexing += o.settle;
    } else {
      t.moves += largest / (o.rapid / 60);
    }
  }
  t.total = t.moves + t.probing + t.indexing;
  return t;
}

TEST(ProbeProgram, TimeEstimateFollowsTheProgram) {
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  ProbeCycle c;
  c.approach = 1.5;
  c.clearance = 7;
  TimingOptions o;
  o.rapid = 8000;
  o.move_feed = 1500;
  o.probe_feed = 150;
  o.rotary_speed = 1800;
  o.settle = 0.7;
  const TimeEstimate est = estimate_time(m, p, c, o);
  for (const auto dialect : {ProbeDialect::LinuxCNC, ProbeDialect::Iso}) {
    ProbeProgramOptions po;
    po.dialect = dialect;
    po.feed = o.move_feed;
    po.probe_feed = o.probe_feed;
    const std::string prog = probe_program(m, p, c, po);
    const TimeEstimate got = time_of_program(prog, dialect == ProbeDialect::LinuxCNC ? "G38.2" : "G31", o, c.approach);
    EXPECT_EQ(got.touches, est.touches);
    EXPECT_NEAR(got.indexing, est.indexing, 1e-9);
    // The program's words have 6 decimals: the times agree to a few 1e-6 s.
    EXPECT_NEAR(got.total, est.total, 1e-5) << got.moves << " " << est.moves << " " << got.probing << " " << est.probing;
    EXPECT_NEAR(got.moves + got.probing, est.moves + est.probing, 1e-5);
  }
  // The tool-point program (--program-coordinates tool-point): world X Y Z, indexations in blocks of
  // at most 5 deg with the linear axes at the safe level, whose world words swing with the turn.
  TimingOptions tp = o;
  tp.tool_point = true;
  const TimeEstimate est_tp = estimate_time(m, p, c, tp);
  ProbeProgramOptions po;
  po.feed = o.move_feed;
  po.probe_feed = o.probe_feed;
  po.coordinates = ProbeCoordinates::ToolPoint;
  const TimeEstimate got = time_of_program(probe_program(m, p, c, po), "G38.2", tp, c.approach);
  EXPECT_EQ(got.touches, est_tp.touches);
  // 6 decimals of mm and deg in the words: a few 1e-6 s.
  EXPECT_NEAR(got.indexing, est_tp.indexing, 1e-5);
  EXPECT_NEAR(got.total, est_tp.total, 1e-5) << got.moves << " " << est_tp.moves;
  EXPECT_NEAR(got.moves + got.probing, est_tp.moves + est_tp.probing, 1e-5);
  // The blocks of a turn move the linear world axes too: the estimate is not the axes program's.
  EXPECT_GT(std::abs(est_tp.total - est.total), 1.0);
}

TEST(ProbeProgram, AgainstPlansTimeIsItsProgramsTime) {
  // plan --against FILE: a plan file gives the features and indexations, not the linear axes'
  // values; its time is that of the program written at its nominal targets (it was once estimated
  // at linear values 0: the RRTTT's Viprey plan 792 s instead of 971 s).
  const Machine m = hu40t();
  const ProbingPlan raw = read_probing_csv(m, kPlans + "hu40t-samba-tango.csv");
  PlanStudyOptions so;
  so.model.estimate = {"EX0C", "EY0C"};
  so.poses = 6;
  so.rotary_step = std::numbers::pi / 2;
  so.threads = 1;
  const PlanStudy s = plan_study(m, raw, raw, so);
  ASSERT_TRUE(s.against_time);
  ProbeProgramOptions po;
  po.feed = so.timing.move_feed;
  po.probe_feed = so.timing.probe_feed;
  const TimeEstimate got =
      time_of_program(probe_program(m, plan_targets(m, raw), so.cycle, po), "G38.2", so.timing, so.cycle.approach);
  EXPECT_EQ(got.touches, s.against_time->touches);
  EXPECT_NEAR(got.total, s.against_time->total, 1e-5);
}

TEST(ProbeProgram, LinuxcncInterpreterReadsTheProgram) {
  if (find_rs274().empty()) GTEST_SKIP() << "LinuxCNC's rs274 is not installed (linuxcnc-uspace)";
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  const ProbeCycle c;
  const auto touches = probe_touches(m, p, c);
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("mtcal-probe-{}", ::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "probe.ngc").string();
  write_probe_program(path, m, p, c, {});
  const Rs274Output out = run_rs274(path, GcodeSetup{});
  std::filesystem::remove_all(dir);
  EXPECT_FALSE(out.missing_end);
  // One STRAIGHT_PROBE per touch, at the touch's end (the program is in mm, G21, and the calls
  // come in the program's units here; the rotary axes in degrees).
  const std::regex call(R"(STRAIGHT_PROBE\(\s*([-0-9.]+),\s*([-0-9.]+),\s*([-0-9.]+),\s*([-0-9.]+),\s*([-0-9.]+),\s*([-0-9.]+))");
  std::size_t i = 0;
  for (auto it = std::sregex_iterator(out.calls.begin(), out.calls.end(), call); it != std::sregex_iterator(); ++it, ++i) {
    ASSERT_LT(i, touches.size());
    const auto& t = touches[i];
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(std::stod((*it)[a + 1]), t.end[*m.axis_index("XYZ"[a])], 1e-3) << "probe " << i;
    EXPECT_NEAR(std::stod((*it)[5]), t.end[*m.axis_index('B')] * 180 / std::numbers::pi, 1e-3);
    EXPECT_NEAR(std::stod((*it)[6]), t.end[*m.axis_index('C')] * 180 / std::numbers::pi, 1e-3);
  }
  EXPECT_EQ(i, touches.size());
}

// The words of one block (a line that starts with G; comments have none): letter -> value.
std::map<char, double> block_words(const std::string& line) {
  std::map<char, double> w;
  if (line.empty() || line[0] != 'G') return w;
  std::istringstream in(line);
  for (std::string tok; in >> tok;)
    if (tok.size() > 1 && std::isupper(static_cast<unsigned char>(tok[0])) && tok[0] != 'G' && tok[0] != 'F')
      w[tok[0]] = std::stod(tok.substr(1));
  return w;
}

TEST(ProbeProgram, ToolPointCoordinatesAreTheNominalToolPoint) {
  // --program-coordinates tool-point (the program for a tool-centre-point kinematics, examples/loop):
  // every probing block's X Y Z is the nominal tool point of the touch's end in the workpiece frame,
  // by ErrorModel::nominal_pose (the chain of kinematics/chain.cpp, not the solver the writer uses),
  // and the indexations turn with the linear axes held at the safe level, at most 5 deg a block.
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  const ProbeCycle c;
  const auto touches = probe_touches(m, p, c);
  ProbeProgramOptions o;
  o.coordinates = ProbeCoordinates::ToolPoint;
  const std::string prog = probe_program(m, p, c, o);
  EXPECT_NE(prog.find("(Coordinates: tool-point world"), std::string::npos);
  const ErrorModel model(m);
  const ToolPointCoordinates world(m);
  const std::size_t tz = *m.axis_index('Z');
  std::size_t i = 0, index_blocks = 0;
  std::istringstream lines(prog);
  std::map<char, double> last_rotary;
  for (std::string line; std::getline(lines, line);) {
    const auto w = block_words(line);
    if (line.rfind("G38.2", 0) == 0) {
      ASSERT_LT(i, touches.size());
      const Vec3 t = model.nominal_pose(touches[i].end).t;
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(w.at("XYZ"[a]), t[a], 2e-6) << line;
      ++i;
    }
    if (line.rfind("G0", 0) == 0 && w.count('B') && w.count('C')) {
      std::vector<double> v(m.axes.size());
      for (std::size_t k = 0; k < m.axes.size(); ++k)
        v[k] = w.at(m.axes[k].letter) * (m.axes[k].kind == AxisKind::Rotary ? std::numbers::pi / 180 : 1.0);
      const auto q = world.axes(v);
      const auto& tr = *m.axes[tz].travel;
      // 1e-5 mm: the words' 6 decimals of a degree (8.7e-9 rad) at up to 700 mm from the rotary axes.
      EXPECT_NEAR(q[tz], m.axes[tz].direction_sign > 0 ? tr.max : tr.min, 1e-5) << line;
      if (!last_rotary.empty()) {
        for (char a : {'B', 'C'}) EXPECT_LE(std::abs(w.at(a) - last_rotary[a]), 5.0 + 1e-6) << line;
      }
      last_rotary = {{'B', w.at('B')}, {'C', w.at('C')}};
      ++index_blocks;
    }
  }
  EXPECT_EQ(i, touches.size());
  EXPECT_GT(index_blocks, 6u);  // the small plan turns C and B between its records

  // The log LinuxCNC writes on that kinematics holds world positions: read back through the nominal
  // chain they give the plan's ball centres (noise-free: to the log's 6 decimals).
  std::string log;
  for (const auto& t : touches) {
    const Vec3 x = model.nominal_pose(t.expected).t;
    log += fmt::format("{:.6f} {:.6f} {:.6f} 0 {:.6f} {:.6f} 0 0 0\n", x[0], x[1], x[2],
                       t.expected[*m.axis_index('B')] * 180 / std::numbers::pi,
                       t.expected[*m.axis_index('C')] * 180 / std::numbers::pi);
  }
  const auto contacts =
      contacts_from_tool_points(m, parse_probe_log(m, log, "probe.txt", ProbeLogFormat::LinuxCNC));
  const ProbingPlan meas = measurements_from_contacts(m, p, c, contacts);
  for (std::size_t r = 0; r < p.records.size(); ++r)
    for (char a : {'X', 'Y', 'Z'})
      EXPECT_NEAR(meas.records[r].q[*m.axis_index(a)], p.records[r].q[*m.axis_index(a)], 2e-6) << r;
  // An ISO log without the rotary values cannot be turned back: named with its line.
  const std::string msg = error_message([&] {
    contacts_from_tool_points(m, parse_probe_log(m, "#5061,#5062,#5063\n1,2,3\n", "probe.csv", ProbeLogFormat::IsoCsv));
  });
  EXPECT_NE(msg.find("probe.csv:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a value of C"), std::string::npos) << msg;
}

TEST(ProbeLog, ContactsBackToMeasurementsThatIdentifyReads) {
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  const ProbeCycle c;
  const auto touches = probe_touches(m, p, c);
  // Noise-free: the ball centres are the targets to the log's 6 decimals.
  const auto contacts = parse_probe_log(m, log_of(m, touches, 0.0, 1), "probe.txt", ProbeLogFormat::LinuxCNC);
  const ProbingPlan meas = measurements_from_contacts(m, p, c, contacts);
  EXPECT_TRUE(meas.measured);
  for (std::size_t i = 0; i < p.records.size(); ++i)
    for (char a : {'X', 'Y', 'Z'})
      EXPECT_NEAR(meas.records[i].q[*m.axis_index(a)], p.records[i].q[*m.axis_index(a)], 2e-6) << i;
  // The measurement file round trip: what identify --measurements reads.
  const ProbingPlan again = parse_probing_csv(m, probing_csv(m, meas), "meas.csv");
  EXPECT_TRUE(again.measured);
  EXPECT_EQ(again.records.size(), p.records.size());
  // The ISO CSV of #5061-#5063 gives the same centres.
  std::string iso = "#5061,#5062,#5063\n";
  for (const auto& t : touches)
    iso += fmt::format("{:.6f},{:.6f},{:.6f}\n", t.expected[*m.axis_index('X')], t.expected[*m.axis_index('Y')],
                       t.expected[*m.axis_index('Z')]);
  const ProbingPlan meas_iso =
      measurements_from_contacts(m, p, c, parse_probe_log(m, iso, "probe.csv", ProbeLogFormat::IsoCsv));
  for (std::size_t i = 0; i < p.records.size(); ++i)
    EXPECT_NEAR(meas_iso.records[i].q[*m.axis_index('X')], meas.records[i].q[*m.axis_index('X')], 1e-9);
}

TEST(ProbeLog, BadLogsSayFileAndLine) {
  const Machine m = hu40t();
  const ProbingPlan p = small_plan(m);
  const ProbeCycle c;
  const auto touches = probe_touches(m, p, c);
  const std::string good = log_of(m, touches, 0.0, 1);
  auto lines = [&] {
    std::vector<std::string> v;
    std::istringstream in(good);
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
  }();
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& l : v) s += l + "\n";
    return s;
  };
  auto meas = [&](const std::string& text) {
    measurements_from_contacts(m, p, c, parse_probe_log(m, text, "probe.txt", ProbeLogFormat::LinuxCNC));
  };
  // Unparsable line.
  auto bad = lines;
  bad[3] = "1.0 2.0 abc 0 0 0 0 0 0";
  std::string msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a number for Z, found 'abc'"), std::string::npos) << msg;
  // Wrong count of numbers.
  bad = lines;
  bad[5] = "1 2 3";
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:6"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 9 numbers"), std::string::npos) << msg;
  // Missing line: the log ends early.
  bad = lines;
  bad.pop_back();
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("expected 34 contacts"), std::string::npos) << msg;
  EXPECT_NE(msg.find("found 33"), std::string::npos) << msg;
  EXPECT_NE(msg.find("contact 34 is missing"), std::string::npos) << msg;
  // Cut after 7 contacts, where a probe that never tripped stops LinuxCNC's program: the message names
  // the missing contact, its touch and record, and LinuxCNC's own words for it.
  bad.resize(7);
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:7"), std::string::npos) << msg;
  EXPECT_NE(msg.find("contact 8 is missing (touch "), std::string::npos) << msg;
  EXPECT_NE(msg.find("G38.2 move finished without making contact"), std::string::npos) << msg;
  // Extra line: located at the first extra one.
  bad = lines;
  bad.push_back(lines.back());
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:35"), std::string::npos) << msg;
  // Out of order: two ball touches of different indexations swapped (B/C differ).
  bad = lines;
  std::swap(bad[4], bad[20]);
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:5"), std::string::npos) << msg;
  EXPECT_NE(msg.find("does not follow the plan"), std::string::npos) << msg;
  // Out of order within one indexation: position far from the expected trip point.
  bad = lines;
  std::swap(bad[0], bad[5]);  // ball 3's pole against ball 4's pole, same B and C
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mm from where the plan's record 1"), std::string::npos) << msg;
  // Non-finite and empty.
  bad = lines;
  bad[2] = "nan 0 0 0 0 0 0 0 0";
  msg = error_message([&] { meas(join(bad)); });
  EXPECT_NE(msg.find("probe.txt:3"), std::string::npos) << msg;
  EXPECT_TRUE(parse_probe_log(m, "\n\n", "probe.txt", ProbeLogFormat::LinuxCNC).empty());
  msg = error_message([&] { meas("\n\n"); });
  EXPECT_NE(msg.find("found 0: contact 1 is missing (touch 1 of the plan's record 1, line"), std::string::npos) << msg;
  // ISO: two numbers only.
  msg = error_message([&] { parse_probe_log(m, "#5061,#5062,#5063\n1,2\n", "probe.csv", ProbeLogFormat::IsoCsv); });
  EXPECT_NE(msg.find("probe.csv:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 3 to 6 numbers"), std::string::npos) << msg;
}

// ---- The first coarse touch: plan --locate's program and probe-log --locate ----

Machine rrttt_loop() { return load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/../loop/rrttt-nominal.yaml"); }

// The loop's artefact: one ball at its rough position (the workpiece frame).
ProbingPlan rough_ball(const Machine& m, const Vec3& at) {
  return parse_probing_csv(m,
                           fmt::format("indexation,A,C,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ\n"
                                       "1,0,0,S,ball,{},{},{},,,,,,\n",
                                       at.x(), at.y(), at.z()),
                           "rough.csv");
}

Vec3 xyz(const Machine& m, const std::vector<double>& q) {
  return Vec3(q[*m.axis_index('X')], q[*m.axis_index('Y')], q[*m.axis_index('Z')]);
}

// Distance from point c to the segment a-b.
double segment_distance(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 d = b - a;
  const double t = d.squaredNorm() > 0 ? std::clamp((c - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * d - c).norm();
}

TEST(LocateProgram, EveryMoveMeetsASphereWithinReachAndNoOtherMoveTouchesIt) {
  // The RRTTT at A = C = 0: axis space is the workpiece frame shifted. For 300 sphere centres within
  // `within` of the rough one (on its bounding sphere too), read from the program's text: every
  // probing move starts outside the sphere and passes through it, every other move after the first
  // (G0 over the ball at the safe level, the G1 change-overs) stays clear of it.
  const Machine m = rrttt_loop();
  const ProbingPlan plan = locate_plan(m, rough_ball(m, Vec3(120, -80, 60)), std::vector<double>(m.axes.size(), 0.0));
  ASSERT_EQ(plan.records.size(), 1u);
  ProbeCycle c;
  c.approach = 0.5;
  LocateOptions lo;
  lo.within = 3;
  const auto touches = locate_touches(m, plan, c, lo);
  ASSERT_EQ(touches.size(), 9u);
  const double rho = (c.ball_diameter + c.tip_diameter) / 2;
  const Vec3 c0 = xyz(m, plan.records[0].q);
  // The pole and the equator start rho + within + approach from the rough centre, the upper ring as far
  // from its axis (the tool axis, Z here) at the ring's height (rho - within) / 2.
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const Vec3 d = xyz(m, touches[i].start) - c0;
    const double h = i < 5 ? 0.0 : (rho - lo.within) / 2;
    EXPECT_NEAR(i < 5 ? d.norm() : d.head<2>().norm(), rho + lo.within + c.approach, 1e-9) << i;
    EXPECT_NEAR(i == 0 ? 0.0 : d.z(), h, 1e-9) << i;
  }
  const std::string prog = locate_program(m, plan, c, lo, {});
  EXPECT_NE(prog.find("(mtcal locating program, LinuxCNC dialect: 1 records, 9 probing moves)"), std::string::npos);
  EXPECT_NE(prog.find("within 3 mm of its rough position"), std::string::npos);
  struct Segment {
    Vec3 a, b;
    bool probe;
  };
  std::vector<Segment> moves;
  std::optional<Vec3> at;
  std::istringstream lines(prog);
  for (std::string line; std::getline(lines, line);) {
    const auto w = block_words(line);
    if (!w.count('X') && !w.count('Z')) continue;
    Vec3 next = at.value_or(Vec3::Zero());
    for (int k = 0; k < 3; ++k)
      if (w.count("XYZ"[k])) next[k] = w.at("XYZ"[k]);
    if (at) moves.push_back({*at, next, line.rfind("G38.2", 0) == 0});
    at = next;
  }
  // A probing move stops where it trips and the next move goes back out along it: checked with the
  // probing move (it starts outside the sphere), not as a move of its own.
  ASSERT_EQ(std::count_if(moves.begin(), moves.end(), [](const Segment& s) { return s.probe; }), 9);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    Vec3 d(g(rng), g(rng), g(rng));
    d *= lo.within * (i % 3 == 0 ? 1.0 : std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng))) / d.norm();
    const Vec3 centre = c0 + d;
    for (std::size_t k = 0; k < moves.size(); ++k) {
      const Segment& s = moves[k];
      if (k > 0 && moves[k - 1].probe) {
        EXPECT_NEAR((s.b - moves[k - 1].a).norm(), 0.0, 1e-9);  // back to the probing move's start
        continue;
      }
      if (s.probe) {
        EXPECT_GT((s.a - centre).norm(), rho + c.approach - 1e-6);
        EXPECT_LT(segment_distance(s.a, s.b, centre), rho - 0.1) << "a probing move misses the sphere at offset "
                                                                 << d.transpose();
      } else {
        EXPECT_GT(segment_distance(s.a, s.b, centre), rho) << "a move touches the sphere at offset " << d.transpose();
      }
    }
  }
  // Farther than half the contact radius: refused, with the limit.
  lo.within = 7.5;
  const std::string msg = error_message([&] { locate_touches(m, plan, c, lo); });
  EXPECT_NE(msg.find("expected the sphere within (0, 7.1] mm of its rough position"), std::string::npos) << msg;
  // No ball: nothing to locate.
  ProbingPlan facets = plan;
  facets.features[0].kind = ProbeFeature::Kind::Facet;
  facets.features[0].normal = Vec3(0, 0, 1);
  EXPECT_NE(error_message([&] { locate_plan(m, facets, std::vector<double>(m.axes.size(), 0.0)); })
                .find("expected a ball to locate"),
            std::string::npos);
}

TEST(LocateProgram, MtcalsReaderAndLinuxcncsInterpreterFollowIt) {
  const Machine m = rrttt_loop();
  const ProbingPlan plan = locate_plan(m, rough_ball(m, Vec3(120, -80, 60)), std::vector<double>(m.axes.size(), 0.0));
  const ProbeCycle c;
  const LocateOptions lo;
  const auto touches = locate_touches(m, plan, c, lo);
  for (const auto coords : {ProbeCoordinates::Axes, ProbeCoordinates::ToolPoint}) {
    ProbeProgramOptions o;
    o.coordinates = coords;
    const std::string prog = locate_program(m, plan, c, lo, o);
    // mtcal's reader, each probing move read as the feed to its end (it simulates no trip).
    GcodeOptions go;
    go.axes = "XYZAC";
    const GcodeProgram g = parse_gcode(std::regex_replace(prog, std::regex("G38\\.2"), "G1"), "locate.ngc", go);
    std::vector<int> probe_lines;
    std::istringstream lines(prog);
    std::string line;
    for (int n = 1; std::getline(lines, line); ++n)
      if (line.rfind("G38.2", 0) == 0) probe_lines.push_back(n);
    ASSERT_EQ(probe_lines.size(), touches.size());
    const ErrorModel model(m);
    std::size_t i = 0;
    for (const auto& mv : g.moves)
      if (i < probe_lines.size() && mv.line == probe_lines[i]) {
        const Vec3 want = coords == ProbeCoordinates::Axes ? xyz(m, touches[i].end) : model.nominal_pose(touches[i].end).t;
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(mv.end[static_cast<std::size_t>(a)], want[a], 2e-6) << "probe " << i;
        ++i;
      }
    EXPECT_EQ(i, touches.size());
  }
  if (find_rs274().empty()) GTEST_SKIP() << "LinuxCNC's rs274 is not installed (linuxcnc-uspace)";
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("mtcal-locate-{}", ::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "locate.ngc").string();
  write_locate_program(path, m, plan, c, lo, {});
  const Rs274Output out = run_rs274(path, GcodeSetup{});
  std::filesystem::remove_all(dir);
  EXPECT_FALSE(out.missing_end);
  const std::regex call(R"(STRAIGHT_PROBE\(\s*([-0-9.]+),\s*([-0-9.]+),\s*([-0-9.]+))");
  std::size_t i = 0;
  for (auto it = std::sregex_iterator(out.calls.begin(), out.calls.end(), call); it != std::sregex_iterator(); ++it, ++i) {
    ASSERT_LT(i, touches.size());
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(std::stod((*it)[a + 1]), touches[i].end[*m.axis_index("XYZ"[a])], 1e-3);
  }
  EXPECT_EQ(i, touches.size());
}

// The log a machine `truth` writes running the locating program (axes coordinates) against a sphere
// at `centre` (workpiece frame) of contact radius rho: on each probing move, where the truth's tool
// point first comes rho from the centre (bisection along the move), plus Gaussian noise on X Y Z;
// "%.6f", nine columns. Stops at a move that never meets it (as LinuxCNC stops the program).
std::string simulated_locate_log(const Machine& truth, const std::vector<ProbeTouch>& touches, const Vec3& centre,
                                 double rho, double noise, std::uint64_t seed) {
  const ErrorModel model(truth);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  auto gap = [&](const ProbeTouch& t, double s) {
    std::vector<double> q(t.start.size());
    for (std::size_t k = 0; k < q.size(); ++k) q[k] = t.start[k] + s * (t.end[k] - t.start[k]);
    return std::make_pair((model.actual_pose(q).t - centre).norm() - rho, q);
  };
  std::string log;
  for (const auto& t : touches) {
    // A move that starts inside the sphere (the approach ran into it) or ends outside it (G38.2 move
    // finished without making contact): LinuxCNC stops the program there.
    if (gap(t, 0.0).first <= 0 || gap(t, 1.0).first > 0) break;
    double lo = 0, hi = 1;
    for (int i = 0; i < 60; ++i) (gap(t, (lo + hi) / 2).first > 0 ? lo : hi) = (lo + hi) / 2;
    const auto q = gap(t, hi).second;
    std::array<double, 9> v{};
    for (std::size_t c = 0; c < 6; ++c)
      if (const auto k = truth.axis_index("XYZABC"[c]))
        v[c] = truth.axes[*k].kind == AxisKind::Rotary ? q[*k] * 180 / std::numbers::pi : q[*k] + noise * g(rng);
    log += fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} 0 0 0\n", v[0], v[1], v[2], v[3], v[4], v[5]);
  }
  return log;
}

// The axis values whose actual tool point on `truth` is p, the rotary ones as in q0 (Newton steps
// on the linear axes): where the machine really stands over a sphere centre.
std::vector<double> actual_at(const Machine& truth, std::vector<double> q, const Vec3& p) {
  const ErrorModel model(truth);
  const std::size_t X = *truth.axis_index('X'), Y = *truth.axis_index('Y'), Z = *truth.axis_index('Z');
  for (int it = 0; it < 20; ++it) {
    Eigen::Matrix3d J;
    const Vec3 f = model.actual_pose(q).t - p;
    for (int a = 0; a < 3; ++a) {
      auto h = q;
      h[std::array{X, Y, Z}[static_cast<std::size_t>(a)]] += 1e-3;
      J.col(a) = (model.actual_pose(h).t - model.actual_pose(q).t) / 1e-3;
    }
    const Vec3 step = J.lu().solve(f);
    q[X] -= step[0], q[Y] -= step[1], q[Z] -= step[2];
  }
  return q;
}

TEST(LocateLog, FindsTheSphereWithinTheProbeNoise) {
  // The loop's RRTTT with its drawn truth (errors --draw 1, the 8 location errors), located at A = 20,
  // C = 40 deg (at A = C = 0 the rotary axes' location errors move nothing): the sphere 2.9 mm from
  // its rough position; contacts with 0.6 um of noise. The located centre is where the nominal
  // machine sees the truth's sphere (the axis values the truth stands at over it, through the nominal
  // chain): within 1.5 um (9 contacts: the centre's u is about 0.6 um / sqrt(3)); the diameter within 5 um.
  const Machine nominal = rrttt_loop();
  ErrorDrawOptions d;
  d.only = {"EX0C", "EY0C", "EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A"};
  const Machine truth = draw_errors(nominal, d).truth;
  const Vec3 rough(120, -80, 60), real = rough + Vec3(1.7, -2.1, 0.9);
  const ProbingPlan plan = locate_plan(nominal, rough_ball(nominal, rough), parse_joint_values(nominal, "A=20,C=40", "at"));
  ProbeCycle c;
  c.approach = 0.5;
  const LocateOptions lo;
  const auto touches = locate_touches(nominal, plan, c, lo);
  const double rho = (c.ball_diameter + c.tip_diameter) / 2;
  const std::string log = simulated_locate_log(truth, touches, real, rho, 0.6e-3, 5);
  const LocateResult r =
      locate_spheres(nominal, plan, c, lo, parse_probe_log(nominal, log, "locate.txt", ProbeLogFormat::LinuxCNC));
  ASSERT_EQ(r.spheres.size(), 1u);
  const auto& s = r.spheres[0];
  const Vec3 seen = ErrorModel(nominal).nominal_pose(actual_at(truth, plan.records[0].q, real)).t;
  EXPECT_GT((seen - real).norm(), 5e-3);  // the truth's errors move it by more than the noise
  EXPECT_LT((s.centre - seen).norm(), 1.5e-3) << (s.centre - seen).transpose();
  EXPECT_NEAR(s.ball_diameter, c.ball_diameter, 5e-3);
  EXPECT_LT(s.rms, 2e-3);
  EXPECT_EQ(s.contacts, 9u);
  EXPECT_FALSE(s.beyond);
  EXPECT_NEAR(s.offset, (s.centre - rough).norm(), 1e-12);
  // The artefact written for plan --artefact: the ball at the located centre.
  const ProbingPlan again = parse_probing_csv(nominal, probing_csv(nominal, r.artefact), "located.csv");
  EXPECT_LT((again.features[0].position - s.centre).norm(), 1e-6);
  // A machine without errors: the located centre is the sphere's, within the noise.
  const std::string clean = simulated_locate_log(nominal, touches, real, rho, 0.6e-3, 6);
  const LocateResult rc =
      locate_spheres(nominal, plan, c, lo, parse_probe_log(nominal, clean, "locate.txt", ProbeLogFormat::LinuxCNC));
  EXPECT_LT((rc.spheres[0].centre - real).norm(), 1.5e-3);
}

TEST(LocateLog, BadLogsAndNoSphereAreSaidWithNothingFound) {
  const Machine m = rrttt_loop();
  const Vec3 rough(120, -80, 60);
  const ProbingPlan plan = locate_plan(m, rough_ball(m, rough), std::vector<double>(m.axes.size(), 0.0));
  ProbeCycle c;
  c.approach = 0.5;
  const LocateOptions lo;
  const auto touches = locate_touches(m, plan, c, lo);
  const double rho = (c.ball_diameter + c.tip_diameter) / 2;
  auto locate = [&](const std::string& log) {
    return locate_spheres(m, plan, c, lo, parse_probe_log(m, log, "locate.txt", ProbeLogFormat::LinuxCNC), "locate.txt");
  };
  // The sphere 5 mm off (more than --locate-within 3): a probing move finds nothing and LinuxCNC
  // stops there: the log is short, the missing contact named.
  const std::string far = simulated_locate_log(m, touches, rough + Vec3(5, 0, 0), rho, 0.0, 1);
  std::size_t logged = static_cast<std::size_t>(std::count(far.begin(), far.end(), '\n'));
  ASSERT_LT(logged, 9u);
  std::string msg = error_message([&] { locate(far); });
  EXPECT_NE(msg.find(fmt::format("expected 9 contacts, found {}: contact {} is missing (touch {} of 9 locating ball S)",
                                 logged, logged + 1, logged + 1)),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("no sphere found within 3 mm of the rough position 120,-80,60"), std::string::npos) << msg;
  // Too few contacts: an empty log, and one cut after 4.
  msg = error_message([&] { locate("\n"); });
  EXPECT_NE(msg.find("locate.txt: expected 9 contacts, found 0: contact 1 is missing"), std::string::npos) << msg;
  const std::string good = simulated_locate_log(m, touches, rough + Vec3(1, 1, -1), rho, 0.0, 1);
  std::vector<std::string> lines;
  std::istringstream in(good);
  for (std::string l; std::getline(in, l);) lines.push_back(l + "\n");
  ASSERT_EQ(lines.size(), 9u);
  msg = error_message([&] { locate(lines[0] + lines[1] + lines[2] + lines[3]); });
  EXPECT_NE(msg.find("locate.txt:4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("contact 5 is missing (touch 5 of 9"), std::string::npos) << msg;
  // An extra contact, and two swapped (each off its own move).
  std::string all;
  for (const auto& l : lines) all += l;
  msg = error_message([&] { locate(all + lines[8]); });
  EXPECT_NE(msg.find("locate.txt:10"), std::string::npos) << msg;
  std::string swapped;
  for (std::size_t i : {0, 2, 1, 3, 4, 5, 6, 7, 8}) swapped += lines[i];
  msg = error_message([&] { locate(swapped); });
  EXPECT_NE(msg.find("locate.txt:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("off its probing move (touch 2 of 9 locating ball S)"), std::string::npos) << msg;
  // Not the ball of the cycle's diameter: a 20 mm sphere where 25.4 mm was said.
  const std::string small = simulated_locate_log(m, touches, rough, (20.0 + c.tip_diameter) / 2, 0.0, 1);
  msg = error_message([&] { locate(small); });
  EXPECT_NE(msg.find("fit a sphere of diameter 20.0000 mm"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no sphere of the ball's diameter found"), std::string::npos) << msg;
  // Contacts not on one sphere (one of them 0.5 mm early along its move): said with the RMS.
  std::istringstream l5(lines[5]);
  std::string bumped;
  {
    std::array<double, 9> v{};
    for (double& x : v) l5 >> x;
    const Vec3 dir = (xyz(m, touches[5].end) - xyz(m, touches[5].start)).normalized();
    for (int k = 0; k < 3; ++k) v[static_cast<std::size_t>(k)] -= 0.5 * dir[k];
    bumped = fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} 0 0 0\n", v[0], v[1], v[2], v[3], v[4], v[5]);
  }
  std::string bad;
  for (std::size_t i = 0; i < 9; ++i) bad += i == 5 ? bumped : lines[i];
  msg = error_message([&] { locate(bad); });
  EXPECT_TRUE(msg.find("are not on one sphere") != std::string::npos ||
              msg.find("no sphere of the ball's diameter found") != std::string::npos)
      << msg;
  // Found, but farther than it was laid out for (3.3 mm, every move still meets it): located, flagged.
  const std::string beyond = simulated_locate_log(m, touches, rough + Vec3(0, 0, 3.3), rho, 0.0, 1);
  const LocateResult rb = locate(beyond);
  EXPECT_TRUE(rb.spheres[0].beyond);
  EXPECT_NEAR(rb.spheres[0].offset, 3.3, 1e-5);
}

}  // namespace
}  // namespace mtcal
