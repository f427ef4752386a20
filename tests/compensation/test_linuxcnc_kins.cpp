// The C module of --format linuxcnc-kins, compiled as plain C with the system's C compiler and a
// small harness (tests/compensation/linuxcnc_kins_harness.c), against the C++ library: on random
// configurations of the four example machines its joints put the model's actual tool point on the
// commanded one to 1e-9 mm, equal the C++ solver's, and its forward inverts its inverse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <unistd.h>

#include <fmt/format.h>

#include "mtcal/compensation/linuxcnc_kins.hpp"
#include "mtcal/identification/error_draw.hpp"
#include "mtcal/io/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/compensation/linuxcnc_probe.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

using namespace mtcal;
namespace fs = std::filesystem;

namespace {

using mtcal::testing::example;

constexpr double kDeg = std::numbers::pi / 180.0;

CompensationOptions quick() {
  CompensationOptions o;
  o.residual_points = 3;
  o.threads = 1;
  return o;
}

std::string run(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  if (rc != 0) throw std::runtime_error("command failed (" + std::to_string(rc) + "): " + cmd);
  return {};
}

// The folders of the compiled harnesses, removed when the test binary ends.
struct TempDirs {
  std::vector<fs::path> dirs;
  ~TempDirs() {
    std::error_code ec;
    for (const auto& d : dirs) fs::remove_all(d, ec);
  }
} temp_dirs;

// Builds the harness for one module; returns the executable.
fs::path build_harness(const std::string& source, const std::string& name, bool probe = false) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("mtcal-kins-{}-{}", ::getpid(), name);
  fs::create_directories(dir);
  temp_dirs.dirs.push_back(dir);
  std::ofstream(dir / "module.c") << source;
  const fs::path exe = dir / "harness";
  // The module must compile warning-free as strict C99 (the LinuxCNC build uses its own flags).
  run(fmt::format("{} -std=c99 -pedantic -Wall -Wextra -Werror -O2 {} '-D{}=\"{}\"' {} -o {} -lm", MTCAL_C_COMPILER,
                  probe ? "-DMTCAL_PROBE_STANDALONE" : "-DMTCAL_KINS_STANDALONE", probe ? "MTP_MODULE" : "MTK_MODULE",
                  (dir / "module.c").string(), probe ? MTCAL_PROBE_HARNESS : MTCAL_KINS_HARNESS, exe.string()));
  return exe;
}

// One example's module and its harness, built once per test binary (the tests below share them).
struct ExampleModule {
  Machine machine;
  LinuxcncKins kins;
  fs::path exe;
  // World rotary order: the rotary letters of the coordinates; joint order: the coordinates.
  // world_slot[axis index of a rotary axis] = its place among the world's rotary coordinates.
  std::vector<std::size_t> world_slot;
};
ExampleModule module_of(Machine m, const std::string& tag) {
  LinuxcncKins k = compensate_linuxcnc_kins(m, quick());
  const fs::path exe = build_harness(linuxcnc_kins_source(k), tag);
  std::vector<std::size_t> world_slot(m.axes.size(), 0);
  std::size_t slot = 0;
  for (const char c : k.coordinates)
    if (c == 'A' || c == 'B' || c == 'C') world_slot[*m.axis_index(c)] = slot++;
  return ExampleModule{std::move(m), std::move(k), exe, std::move(world_slot)};
}
const ExampleModule& example_module(const std::string& f) {
  static std::map<std::string, ExampleModule> built;
  auto it = built.find(f);
  if (it == built.end()) it = built.emplace(f, module_of(example(f.c_str()), f.substr(0, 4))).first;
  return it->second;
}

// The loop's RRTTT (examples/loop) with the truth loop.sh draws by default: seed 1, its 8 location
// errors, ECC as a 5-point table (errors --draw 1 --draw-only ... --draw-table ECC --draw-table-points 5).
Machine loop_truth_with_table() {
  const Machine nominal = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/../loop/rrttt-nominal.yaml");
  ErrorDrawOptions d;
  d.seed = 1;
  d.only = {"EX0C", "EY0C", "EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A"};
  d.tables = {"ECC"};
  d.table_points = 5;
  return draw_errors(nominal, d).truth;
}

std::vector<std::vector<double>> drive(const fs::path& exe, const std::string& input) {
  const fs::path in = exe.parent_path() / "in.txt", out = exe.parent_path() / "out.txt";
  std::ofstream(in) << input;
  run(fmt::format("{} < {} > {}", exe.string(), in.string(), out.string()));
  std::ifstream f(out);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(f, line);) {
    std::istringstream s(line);
    std::vector<double> r;
    for (double v; s >> v;) r.push_back(v);
    rows.push_back(r);
  }
  return rows;
}

// The module's inverse on 100 random poses: the model's actual tool point on the command (1e-9 mm),
// the C++ solver's joints, and its forward back to the command.
void expect_module_matches_library(const ExampleModule& em, const std::string& f) {
  const Machine& m = em.machine;
  const LinuxcncKins& k = em.kins;
  const fs::path& exe = em.exe;
  const CommandedJointSolver s(m);  // the library, with the full model (directions unused)
  const std::size_t n = m.axes.size();
  const std::vector<std::size_t>& world_slot = em.world_slot;
  const auto q = mtcal::testing::random_configurations(m, 100, 21);
  std::string input;
  std::vector<CommandedPose> poses;
  std::vector<double> lengths;
  for (std::size_t r = 0; r < 100; ++r) {
    const double L = r % 3 == 0 ? 0.0 : r % 3 == 1 ? m.tool.length : 37.25;
    const CommandedPose p = s.nominal_forward({q.data() + r * n, n}, L);
    std::vector<double> w(3 + s.rotary_count());
    for (int i = 0; i < 3; ++i) w[static_cast<std::size_t>(i)] = p.point[i];
    for (std::size_t j = 0; j < s.rotary_count(); ++j) w[3 + world_slot[s.rotary_axes()[j]]] = p.rotary[j] / kDeg;
    input += fmt::format("I {:.17g}", L);
    for (double v : w) input += fmt::format(" {:.17g}", v);
    input += "\n";
    poses.push_back(p);
    lengths.push_back(L);
  }
  const auto rows = drive(exe, input);
  ASSERT_EQ(rows.size(), 100u) << f;
  std::string forward_input;
  for (std::size_t r = 0; r < 100; ++r) {
    ASSERT_EQ(rows[r].size(), 3 + n) << f;
    ASSERT_EQ(rows[r][0], 0.0) << f << " inverse status, row " << r;
    // The C joints (LinuxCNC order, mm and deg) in chain order, internal units.
    std::vector<double> qc(n);
    for (std::size_t a = 0; a < n; ++a) {
      const double v = rows[r][3 + k.coordinates.find(m.axes[a].letter)];
      qc[a] = m.axes[a].kind == AxisKind::Rotary ? v * kDeg : v;
    }
    // Independent of the C: the C++ model's actual tool point at the C joints.
    EXPECT_LE((s.actual_pose(qc, lengths[r]).t - poses[r].point).norm(), 1e-9) << f << " row " << r;
    const auto lib = s.inverse(poses[r], lengths[r]);
    ASSERT_TRUE(lib.converged);
    for (std::size_t a = 0; a < n; ++a) EXPECT_NEAR(qc[a], lib.q[a], 1e-9) << f << " axis " << m.axes[a].letter;
    forward_input += fmt::format("F {:.17g}", lengths[r]);
    for (std::size_t j = 0; j < n; ++j) forward_input += fmt::format(" {:.17g}", rows[r][3 + j]);
    forward_input += "\n";
  }
  const auto back = drive(exe, forward_input);
  ASSERT_EQ(back.size(), 100u);
  for (std::size_t r = 0; r < 100; ++r) {
    ASSERT_EQ(back[r][0], 0.0) << f << " forward status";
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[r][1 + static_cast<std::size_t>(i)], poses[r].point[i], 1e-9) << f;
    for (std::size_t j = 0; j < s.rotary_count(); ++j)
      EXPECT_NEAR(back[r][4 + world_slot[s.rotary_axes()[j]]], poses[r].rotary[j] / kDeg, 1e-9) << f;
  }
}

}  // namespace

TEST(LinuxcncKinsModule, GeneratedCMatchesTheLibraryOnEveryExample) {
  for (const char* f : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"})
    expect_module_matches_library(example_module(f), f);
}

// The loop's truth holds a motion-error table (issue 33): the module of a model with that table (what
// compensate writes from identify's estimate of it) matches the library as on the examples.
TEST(LinuxcncKinsModule, GeneratedCMatchesTheLibraryWithTheLoopsTable) {
  Machine truth = loop_truth_with_table();
  const auto* t = std::get_if<Table>(&truth.axes[*truth.axis_index('C')].motion[5].form());
  ASSERT_NE(t, nullptr);
  ASSERT_EQ(t->positions.size(), 5u);
  double big = 0.0;  // the largest |value|: at least the draw's smallest angle, 10 urad
  EXPECT_EQ(t->forward[2], 0.0);  // zero at the axis' zero (C = 0 is the middle node)
  for (double v : t->forward) big = std::max(big, std::abs(v));
  EXPECT_GE(big, 10e-6);
  expect_module_matches_library(module_of(std::move(truth), "loop-table"), "loop truth with ECC table");
}

// LinuxCNC's G43 convention (src/emc/kinematics/trtfuncs.c, 5axiskins.c; docs/compensation-linuxcnc-kins.md):
// LinuxCNC hands the kinematics the programmed point plus the tool length offset O along the tool axis
// letter (z on the examples), and the module's tool-offset pin carries O. The tool tip must land on the
// programmed point, world - O e_tool, with a tool tool-length + O long along the actual tool axis: the
// library's actual pose at the C joints says where the tip is, and the library's inverse for that tip
// and length gives the joints. Table-table (RRTTT, HU40T), head-head and 3-axis.
TEST(LinuxcncKinsModule, ToolOffsetOfG43PutsTheTipOnTheProgrammedPoint) {
  for (const char* f : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"}) {
    const ExampleModule& em = example_module(f);
    const Machine& m = em.machine;
    const LinuxcncKins& k = em.kins;
    const fs::path& exe = em.exe;
    const CommandedJointSolver s(m);
    const std::size_t n = m.axes.size();
    ASSERT_EQ(m.tool.tool_axis, 2) << f;  // the examples' tools point along -z: G43's Z offset is the length
    const Vec3 e_tool = Vec3::UnitZ();
    const std::vector<std::size_t>& world_slot = em.world_slot;
    constexpr std::size_t kRows = 48;
    const auto q = mtcal::testing::random_configurations(m, kRows, 33);
    std::string input;
    std::vector<CommandedPose> tips;
    std::vector<std::vector<double>> worlds;
    std::vector<double> pin_length, offset;
    for (std::size_t r = 0; r < kRows; ++r) {
      const double O = r % 3 == 0 ? 50.0 : r % 3 == 1 ? 137.5 : 12.25;  // tool table lengths
      const double L = r % 2 ? 0.0 : 7.5;                                // tool-length pin
      const CommandedPose tip = s.nominal_forward({q.data() + r * n, n}, L + O);
      std::vector<double> w(3 + s.rotary_count());
      for (int i = 0; i < 3; ++i) w[static_cast<std::size_t>(i)] = tip.point[i] + O * e_tool[i];  // what G43 hands over
      for (std::size_t j = 0; j < s.rotary_count(); ++j) w[3 + world_slot[s.rotary_axes()[j]]] = tip.rotary[j] / kDeg;
      input += fmt::format("i {:.17g} {:.17g}", L, O);
      for (double v : w) input += fmt::format(" {:.17g}", v);
      input += "\n";
      tips.push_back(tip);
      worlds.push_back(w);
      pin_length.push_back(L);
      offset.push_back(O);
    }
    const auto rows = drive(exe, input);
    ASSERT_EQ(rows.size(), kRows) << f;
    std::string forward_input;
    double worst_tip = 0.0;
    for (std::size_t r = 0; r < kRows; ++r) {
      ASSERT_EQ(rows[r].size(), 3 + n) << f;
      ASSERT_EQ(rows[r][0], 0.0) << f << " inverse status, row " << r;
      std::vector<double> qc(n);
      for (std::size_t a = 0; a < n; ++a) {
        const double v = rows[r][3 + k.coordinates.find(m.axes[a].letter)];
        qc[a] = m.axes[a].kind == AxisKind::Rotary ? v * kDeg : v;
      }
      const double L = pin_length[r] + offset[r];
      // The model's tip with a tool L long along its actual axis (a tilted tool included).
      const Affine actual = s.actual_pose(qc, L);
      worst_tip = std::max(worst_tip, (actual.t - tips[r].point).norm());
      EXPECT_LE((actual.t - tips[r].point).norm(), 1e-9) << f << " row " << r;
      const auto lib = s.inverse(tips[r], L);
      ASSERT_TRUE(lib.converged);
      for (std::size_t ax = 0; ax < n; ++ax) EXPECT_NEAR(qc[ax], lib.q[ax], 1e-9) << f << " axis " << m.axes[ax].letter;
      forward_input += fmt::format("f {:.17g} {:.17g}", pin_length[r], offset[r]);
      for (std::size_t j = 0; j < n; ++j) forward_input += fmt::format(" {:.17g}", rows[r][3 + j]);
      forward_input += "\n";
    }
    const auto back = drive(exe, forward_input);
    ASSERT_EQ(back.size(), kRows);
    for (std::size_t r = 0; r < kRows; ++r) {
      ASSERT_EQ(back[r][0], 0.0) << f << " forward status";
      for (std::size_t i = 0; i < worlds[r].size(); ++i) EXPECT_NEAR(back[r][1 + i], worlds[r][i], 1e-9) << f << " row " << r;
    }
    std::printf("[ measured ] %s: G43 tool offset, %zu configurations: |tip - programmed point| <= %.2g mm\n", f, kRows,
                worst_tip);
  }
}

// trt-kins' inverse at the rotary zero (trtfuncs.c: P = R (pos - dz e_z) + dz e_z = pos for R = I) and
// 5axiskins' (pivot-length grows with the offset, the joints do not move while the tool is vertical):
// G43 changes no joint there. The module on the error-free machine must do the same: its joints with
// offset O equal its joints with none, to 1e-9 mm.
TEST(LinuxcncKinsModule, G43AtRotaryZeroMovesNoJointOnTheErrorFreeMachine) {
  for (const char* f : {"rrttt-table-table.yaml", "head-head-5axis.yaml"}) {
    Machine m = example(f);
    m.clear_errors();
    LinuxcncKinsOptions ko;
    ko.check_points = 2;  // the pre-check is not what this test is about
    const LinuxcncKins k = compensate_linuxcnc_kins(m, quick(), ko);
    const fs::path exe = build_harness(linuxcnc_kins_source(k), "g43-zero-" + std::string(f).substr(0, 4));
    std::string input;
    for (const double O : {50.0, 137.5})
      for (const char* w : {"0 0 0 0 0", "120.5 -80 35 0 0", "-210 140 -60 0 0"})
        input += fmt::format("I 0 {}\ni 0 {:.17g} {}\n", w, O, w);
    const auto rows = drive(exe, input);
    ASSERT_EQ(rows.size(), 12u) << f;
    for (std::size_t r = 0; r < rows.size(); r += 2) {
      ASSERT_EQ(rows[r][0], 0.0) << f;
      ASSERT_EQ(rows[r + 1][0], 0.0) << f;
      for (std::size_t j = 3; j < rows[r].size(); ++j) EXPECT_NEAR(rows[r + 1][j], rows[r][j], 1e-9) << f << " row " << r;
    }
  }
}

TEST(LinuxcncKinsModule, NonFiniteInputIsAnErrorNotAPosition) {
  const Machine m = example("head-head-5axis.yaml");
  const LinuxcncKins k = compensate_linuxcnc_kins(m, quick());
  const fs::path exe = build_harness(linuxcnc_kins_source(k), "nan");
  const auto rows = drive(exe,
                         "I 150 nan 0 0 0 0\nI inf 0 0 0 0 0\nI 150 0 0 1e300 0 0\nF 150 nan 0 0 0 0\n"
                         "i 0 nan 0 0 0 0 0\ni 0 inf 0 0 0 0 0\nf 0 nan 0 0 0 0 0\ni 0 50 0 0 nan 0 0\n");
  ASSERT_EQ(rows.size(), 8u);
  for (const auto& r : rows) EXPECT_LT(r[0], 0.0);
}

TEST(LinuxcncKinsModule, UnconvergedAtTheCapIsAnError) {
  // One step allowed: the example's errors need more, and the module must say so.
  const Machine m = example("hu40t-wCBXfYZt.yaml");
  LinuxcncKins k = compensate_linuxcnc_kins(m, quick());
  k.solver.max_iterations = 1;
  const fs::path exe = build_harness(linuxcnc_kins_source(k), "cap");
  const auto rows = drive(exe, "I 150 100 50 -20 10 30\n");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0][0], -2.0);
}

// The fault of issue 33 "a module that fails to converge mid-program" (tests/linuxcnc/loop_test.py,
// no-converge, runs it in LinuxCNC): a model whose EXX table rises 0.3 mm over 0.2 mm (X = 40..40.2)
// and falls back over 20 mm passes compensate's pre-check (its grid misses the stretch), and there
// the module's fixed-point step with the nominal Jacobian overshoots by the slope, 1.5, and ends at
// the cap (-2), as the library's does; outside the stretch both converge. (A fall over 2 mm, slope
// 0.15, was too slow for the cap too: 0.15^12 of 0.2 mm is above the 1e-11 mm tolerance.)
TEST(LinuxcncKinsModule, ASteepTableStretchIsUnconvergedThereOnly) {
  Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/../loop/rrttt-nominal.yaml");
  apply_parameters(m,
                   "mtcal_parameters: 1\nerrors:\n  EXX: {unit: mm, argument_unit: mm, table: {positions: [-355, 40, 40.2, "
                   "60.2, 355], forward: [0, 0, 0.3, 0, 0]}}\n",
                   "steep.yaml");
  const ExampleModule em = module_of(m, "steep");  // compensate writes it
  const CommandedJointSolver s(m);
  std::string input;
  const std::vector<double> xs = {39.0, 40.05, 40.1, 40.15, 41.0};
  for (double x : xs) {
    std::vector<double> q(m.axes.size(), 0.0);
    q[*m.axis_index('X')] = x;
    q[*m.axis_index('Z')] = -50.0;
    const CommandedPose p = s.nominal_forward(q, m.tool.length);
    input += fmt::format("I {:.17g} {:.17g} {:.17g} {:.17g} 0 0\n", m.tool.length, p.point[0], p.point[1], p.point[2]);
    const bool steep = x > 40.0 && x < 40.2;
    EXPECT_EQ(s.inverse(p, m.tool.length).converged, !steep) << "library at X=" << x;
  }
  const auto rows = drive(em.exe, input);
  ASSERT_EQ(rows.size(), xs.size());
  for (std::size_t r = 0; r < xs.size(); ++r) {
    const bool steep = xs[r] > 40.0 && xs[r] < 40.2;
    EXPECT_EQ(rows[r][0], steep ? -2.0 : 0.0) << "module at X=" << xs[r];
  }
}

TEST(LinuxcncKinsModule, RefusesWhatItCannotRepresentOrReach) {
  // A topology with two linear axes.
  Machine two = example("vmc-3axis.yaml");
  two.axes.pop_back();
  two.topology.axes.pop_back();
  try {
    compensate_linuxcnc_kins(two, quick());
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("exactly three"), std::string::npos) << e.what();
  }
  // The commanded travel up to the joint limits: the correction has no room.
  const Machine m = example("vmc-3axis.yaml");
  CompensationOptions o = quick();
  for (const auto& ax : m.axes) o.sampling.push_back({ax.letter, ax.travel->min, ax.travel->max, 3});
  try {
    compensate_linuxcnc_kins(m, o);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("leaves its travel"), std::string::npos) << e.what();
  }
  // Errors too large for the fixed cap: not converged on the pre-check grid, with the configuration.
  Machine wild = example("head-head-5axis.yaml");
  wild.set_parameter("EB0Z", 0.3);  // 0.3 rad of squareness
  LinuxcncKinsOptions ko;
  ko.solver.max_iterations = 3;
  try {
    compensate_linuxcnc_kins(wild, quick(), ko);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not converge at X="), std::string::npos) << e.what();
  }
  // A module name that is not a C identifier.
  ko = {};
  ko.module_name = "my-kins";
  EXPECT_THROW(compensate_linuxcnc_kins(m, quick(), ko), InputError);
}

TEST(LinuxcncKinsModule, ReversalTablesCancelTheOwnAxisDirectionTerms) {
  // Head-head: EXX has forward/backward runs, EYY and EZZ reversal terms. A type-1 column is the
  // correction: value(q, +) - value(q, 0) of the axis's own error, negated (direction sign +1).
  const Machine m = example("head-head-5axis.yaml");
  const LinuxcncKins k = compensate_linuxcnc_kins(m, quick());
  std::string joints;
  for (const auto& t : k.reversal_tables) joints += t.axis;
  EXPECT_EQ(joints, "XYZAC");
  const auto& y = *std::find_if(k.reversal_tables.begin(), k.reversal_tables.end(), [](const auto& t) { return t.axis == 'Y'; });
  // EYY reversal 1.4 um: forward column -1.4 um, reverse +1.4 um everywhere.
  for (std::size_t i = 0; i < y.nominal.size(); ++i) {
    EXPECT_NEAR(y.forward[i], -1.4e-3, 1e-12);
    EXPECT_NEAR(y.reverse[i], 1.4e-3, 1e-12);
  }
  // The residual with the module and the tables is below the one without the tables.
  EXPECT_LT(k.summary.residual.max_norm_after, 0.2 * k.summary.residual.max_norm_before);
}

// The simulated probe of mtcal linuxcnc-probe (issue 31 item 4): its generated C, compiled as plain C
// with a harness, puts the stylus tip where the C++ library's actual chain puts it (1e-9 mm) and
// measures the gap to the nearest sphere; a non-finite joint is an error (the component then holds
// the probe tripped), never a position.
// The examples, and the loop's truth with its ECC table (issue 33: the simulated probe evaluates the
// table the loop's truth holds).
TEST(LinuxcncProbeComponent, TipAndGapMatchTheLibrary) {
  for (const char* f : {"rrttt-table-table.yaml", "hu40t-wCBXfYZt.yaml", "head-head-5axis.yaml", "loop-table"}) {
    const Machine m = std::string(f) == "loop-table" ? loop_truth_with_table() : example(f);
    LinuxcncProbeOptions p;
    p.spheres = {{Vec3(120, -80, 60), 25.4}, {Vec3(-150, 40, 10), 30.0}};
    p.stylus_diameter = 3.0;
    const LinuxcncKins k = linuxcnc_kins_model(m, p.component_name);
    const fs::path exe = build_harness(linuxcnc_probe_source(k, p), "probe-" + std::string(f).substr(0, 4), true);
    const CommandedJointSolver s(m);  // the library's actual chain (direction of motion 0)
    const std::size_t n = m.axes.size();
    const auto q = mtcal::testing::random_configurations(m, 50, 5);
    std::string input;
    for (std::size_t r = 0; r < 50; ++r) {
      const double L = r % 2 ? m.tool.length : 12.5;
      input += fmt::format("{:.17g}", L);
      for (const char c : k.coordinates) {
        const std::size_t a = *m.axis_index(c);
        input += fmt::format(" {:.17g}", to_user_units(m.axes[a], q[r * n + a]));
      }
      input += "\n";
    }
    const auto rows = drive(exe, input);
    ASSERT_EQ(rows.size(), 50u) << f;
    for (std::size_t r = 0; r < 50; ++r) {
      ASSERT_EQ(rows[r].size(), 6u);
      ASSERT_EQ(rows[r][0], 0.0) << f << " row " << r;
      const double L = r % 2 ? m.tool.length : 12.5;
      const Vec3 tip = s.actual_pose({q.data() + r * n, n}, L).t;
      // 1e-8 mm: up to 1.7e-9 mm (2e-12 relative) between the C chain and the library's was measured at
      // the machine file's tool length on the RRTTT, the library's own rounding order.
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(rows[r][3 + static_cast<std::size_t>(i)], tip[i], 1e-8) << f << " row " << r;
      const double g0 = (tip - p.spheres[0].centre).norm() - (25.4 + 3.0) / 2;
      const double g1 = (tip - p.spheres[1].centre).norm() - (30.0 + 3.0) / 2;
      EXPECT_NEAR(rows[r][1], std::min(g0, g1), 1e-8) << f;
      EXPECT_EQ(rows[r][2], g0 <= g1 ? 0.0 : 1.0) << f;
    }
  }
}

TEST(LinuxcncProbeComponent, TripsOnTheSurfaceAndRefusesNonFiniteJoints) {
  // The vmc: the tip at the sphere's pole from above, exactly at contact by the library's chain.
  const Machine m = example("vmc-3axis.yaml");
  const CommandedJointSolver s(m);
  const std::vector<double> q0(m.axes.size(), 0.0);
  const Vec3 tip0 = s.actual_pose(q0, m.tool.length).t;
  LinuxcncProbeOptions p;
  p.spheres = {{tip0 - Vec3(0, 0, 10.0), 16.0}};  // contact distance (16 + 4) / 2 = 10 mm
  p.stylus_diameter = 4.0;
  const fs::path exe = build_harness(linuxcnc_probe_source(linuxcnc_kins_model(m, p.component_name), p), "probe-trip", true);
  const auto rows = drive(exe, fmt::format("{0:.17g} 0 0 0\n{0:.17g} nan 0 0\ninf 0 0 0\n", m.tool.length));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0][0], 0.0);
  EXPECT_NEAR(rows[0][1], 0.0, 1e-12);  // on the surface: gap 0, the component trips (gap <= 0)
  EXPECT_LT(rows[1][0], 0.0);
  EXPECT_LT(rows[2][0], 0.0);
  // Bad options: no sphere, a zero diameter.
  LinuxcncProbeOptions none;
  EXPECT_THROW(linuxcnc_probe_source(linuxcnc_kins_model(m, "mtcal_probe"), none), InputError);
  LinuxcncProbeOptions zero;
  zero.spheres = {{Vec3::Zero(), 0.0}};
  EXPECT_THROW(linuxcnc_probe_source(linuxcnc_kins_model(m, "mtcal_probe"), zero), InputError);
}

// Every corrected joint inside its travel at `count` random configurations of the commanded travel
// the summary states (a denser check than the 5-point pre-check grid it was chosen on); returns the
// largest |corrected - commanded| met per axis (user units).
std::vector<double> check_commanded_travel(const Machine& m, const CompensationSummary& s, std::size_t count) {
  const CommandedJointSolver solver(m);
  std::mt19937_64 rng(7);
  std::vector<double> largest(m.axes.size(), 0.0);
  EXPECT_EQ(s.commanded.size(), m.axes.size());
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<double> q(m.axes.size());
    for (std::size_t a = 0; a < m.axes.size(); ++a) {
      const auto& r = s.commanded[a];
      EXPECT_EQ(r.axis, m.axes[a].letter);
      // The corners too: every 8th configuration takes the ends.
      const double u = i % 8 == 0 ? static_cast<double>((i / 8 + a) % 2) : std::uniform_real_distribution<double>(0, 1)(rng);
      q[a] = (r.lo + u * (r.hi - r.lo)) * joint_unit_factor(m.axes[a]);
    }
    const auto res = solver.inverse(solver.nominal_forward(q, m.tool.length), m.tool.length);
    EXPECT_TRUE(res.converged);
    for (std::size_t a = 0; a < m.axes.size(); ++a) {
      const Axis& ax = m.axes[a];
      EXPECT_GE(res.q[a], ax.travel->min) << ax.letter << " at configuration " << i;
      EXPECT_LE(res.q[a], ax.travel->max) << ax.letter << " at configuration " << i;
      largest[a] = std::max(largest[a], std::abs(res.q[a] - q[a]) / joint_unit_factor(ax));
    }
  }
  return largest;
}

TEST(LinuxcncKinsModule, CompensateChoosesTheRoomItsCorrectionsNeed) {
  // The vmc with a squareness of 1 mm/m: X is corrected by up to 0.25 mm at the Y travel's ends,
  // more than the 0.1 mm the commanded travel used to keep from the joint limits.
  Machine m = example("vmc-3axis.yaml");
  m.set_parameter("EC0Y", 1e-3);
  const LinuxcncKins k = compensate_linuxcnc_kins(m, quick());
  const auto& x = k.summary.commanded[*m.axis_index('X')];
  EXPECT_FALSE(x.given);
  EXPECT_GT(x.largest_correction, 0.2);
  EXPECT_GE(x.margin, 1.25 * x.largest_correction);
  EXPECT_NEAR(x.lo, -400 + x.margin, 1e-9);
  EXPECT_NEAR(x.hi, 400 - x.margin, 1e-9);
  EXPECT_NE(x.why.find("largest correction over the travel"), std::string::npos) << x.why;
  const auto largest = check_commanded_travel(m, k.summary, 2000);
  EXPECT_GT(largest[*m.axis_index('X')], 0.2);
  // The old fixed room (0.1 mm) has a corrected X outside the travel: refused, as before.
  CompensationOptions old = quick();
  for (const auto& ax : m.axes) old.sampling.push_back({ax.letter, ax.travel->min + 0.1, ax.travel->max - 0.1, 3});
  try {
    compensate_linuxcnc_kins(m, old);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the corrected joint X leaves its travel"), std::string::npos) << e.what();
  }
  // A range given for an axis (--range) is the commanded travel there, said to be given; the others computed.
  CompensationOptions one = quick();
  one.sampling.push_back({'Y', -200, 150, 3});
  const LinuxcncKins g = compensate_linuxcnc_kins(m, one);
  const auto& y = g.summary.commanded[*m.axis_index('Y')];
  EXPECT_TRUE(y.given);
  EXPECT_EQ(y.lo, -200);
  EXPECT_EQ(y.hi, 150);
  EXPECT_EQ(y.why, "given");
  EXPECT_FALSE(g.summary.commanded[*m.axis_index('X')].given);
  // Errors whose corrections need more room than the travel has: said, nothing chosen.
  Machine huge = example("vmc-3axis.yaml");
  huge.set_parameter("EC0Y", 3.5);  // 3.5 rad: X corrected by far more than its travel
  EXPECT_THROW(compensate_linuxcnc_kins(huge, quick()), InputError);
}

TEST(LinuxcncKinsModule, CompensateChoosesTheRoomOnTheLoopsMachines) {
  // The loop's machines (examples/loop) with their drawn truths (errors --draw 1 --draw-only the
  // estimated location errors): without --range every corrected joint of the commanded travel stays
  // inside the travel, and the commanded travel is wider than the loop's hand-given one (5 mm / 5 deg
  // inside; tests/linuxcnc/loop_test.py).
  struct Case {
    const char* file;
    const char* estimate;
    double hand_room;
  };
  for (const Case& c : {Case{"rrttt-nominal.yaml", "EX0C,EY0C,EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A", 5.0},
                        Case{"hu40t-nominal.yaml", "EX0C,EY0C,EA0C,EB0C,EX0B,EZ0B,EA0B,EC0B", 5.0}}) {
    const Machine nominal = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/../loop/" + c.file);
    ErrorDrawOptions d;
    d.seed = 1;
    for (std::string s = c.estimate; !s.empty();) {
      const auto comma = s.find(',');
      d.only.push_back(s.substr(0, comma));
      s = comma == std::string::npos ? "" : s.substr(comma + 1);
    }
    const Machine truth = draw_errors(nominal, d).truth;
    const LinuxcncKins k = compensate_linuxcnc_kins(truth, quick());
    check_commanded_travel(truth, k.summary, 500);
    for (const auto& r : k.summary.commanded) {
      EXPECT_FALSE(r.given);
      EXPECT_LT(r.margin, c.hand_room) << c.file << " " << r.axis;
      EXPECT_GE(r.margin, 1.25 * r.largest_correction) << c.file << " " << r.axis;
    }
  }
}
