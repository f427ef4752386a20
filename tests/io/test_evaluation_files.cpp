// Readers and writer of the acceptance tests' files: round trip of the ballbar trace, sources kept, bad input located.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

#include "input_errors.hpp"

using namespace mtcal;
using mtcal::testing::error_at;
using mtcal::testing::write_temp;

namespace {}  // namespace

TEST(EvaluationFiles, BallbarTraceRoundTrip) {
  std::vector<TracePoint> trace;
  for (int k = 0; k < 36; ++k) {
    const double a = 2 * std::numbers::pi * k / 36;
    trace.push_back({k % 2 ? CircleDirection::CW : CircleDirection::CCW, a, 150.0 + 1e-3 * std::sin(3 * a)});
  }
  const std::string path = (std::filesystem::temp_directory_path() / "mtcal-trace-roundtrip.csv").string();
  write_ballbar_csv(path, trace);
  const BallbarTrace back = read_ballbar_csv(path);
  EXPECT_EQ(back.source, path);
  ASSERT_EQ(back.points.size(), trace.size());
  for (std::size_t i = 0; i < trace.size(); ++i) {
    EXPECT_EQ(back.points[i].direction, trace[i].direction);
    EXPECT_NEAR(back.points[i].angle, trace[i].angle, 1e-8);  // 6 decimals of a degree
    EXPECT_NEAR(back.points[i].radius, trace[i].radius, 1e-9);
  }
  EXPECT_EQ(ballbar_csv(back.points).substr(0, 30), "direction,angle_deg,radius_mm\n");
}

TEST(EvaluationFiles, BallbarBadCellsAreLocated) {
  const auto bad_dir = write_temp("mtcal-bb-bad.csv", "direction,angle_deg,radius_mm\nccw,0,150\nup,1,150\n");
  const auto w = error_at([&] { read_ballbar_csv(bad_dir); });
  EXPECT_EQ(w.file, bad_dir);
  EXPECT_EQ(w.line, 3);
  EXPECT_EQ(w.field, "direction");
  const auto bad_r = write_temp("mtcal-bb-bad2.csv", "# c\ndirection,angle_deg,radius_mm\ncw,0,-1\n");
  const auto w2 = error_at([&] { read_ballbar_csv(bad_r); });
  EXPECT_EQ(w2.line, 3);
  EXPECT_EQ(w2.field, "radius_mm");
}

TEST(EvaluationFiles, PositioningKeepsItsSourceAndDetectsTheForm) {
  const auto csv = write_temp("mtcal-pos.csv", "target,run,direction,measured\n0,1,up,0.001\n0,1,down,0.002\n");
  const auto r = read_positioning_file(csv, "auto", "um");
  EXPECT_EQ(r.source, csv);
  EXPECT_EQ(r.unit, "um");
  ASSERT_EQ(r.targets.size(), 1u);
  const auto dat =
      write_temp("mtcal-pos.txt", "UNIT=mm\nTGT_DATA[0]=0\nREF_DATA_FWD[0,0]=0.001\nREF_DATA_BWD[0,0]=0.002\n");
  const auto d = read_positioning_file(dat, "auto", "um");  // TGT_DATA[ makes it the .dat form
  EXPECT_EQ(d.source, dat);
  EXPECT_EQ(d.unit, "mm");
  ASSERT_EQ(d.up.size(), 1u);
  EXPECT_DOUBLE_EQ(d.up[0][0], 0.001);
  const auto w = error_at([&] { read_positioning_dat(write_temp("mtcal-pos-bad.dat", "UNIT=mm\nTGT_DATA[0]=x\n")); });
  EXPECT_EQ(w.line, 2);
  EXPECT_EQ(w.field, "TGT_DATA[0]");
  const auto w2 = error_at([&] {
    read_positioning_csv(write_temp("mtcal-pos-bad.csv", "target,run,direction,measured\n0,1.5,up,0\n"), "mm");
  });
  EXPECT_EQ(w2.line, 2);
  EXPECT_EQ(w2.field, "run");
}

// Hostile .dat keys: a 50 KB key (once a stack overflow in std::regex), huge indices (once
// "stol" as the whole message and undefined behaviour), control characters in keys and units.
TEST(EvaluationFiles, PositioningDatRefusesHostileKeysWithShortMessages) {
  auto message_of = [](const std::string& name, const std::string& text) {
    try {
      read_positioning_dat(write_temp(name, text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "no InputError for " << name;
    return std::string();
  };
  const std::string long_key = "UNIT=mm\nTGT_DATA[" + std::string(50000, '1') + "]=0\n";
  const std::string m1 = message_of("mtcal-pos-long.dat", long_key);
  EXPECT_LT(m1.size(), 400u) << m1;
  EXPECT_NE(m1.find("9 digits"), std::string::npos) << m1;
  const std::string m2 = message_of("mtcal-pos-huge.dat", "TGT_DATA[0]=0\nREF_DATA_FWD[0,99999999999999999999]=1\n");
  EXPECT_NE(m2.find(":2:"), std::string::npos) << m2;
  EXPECT_EQ(m2.find("stol"), std::string::npos) << m2;
  const std::string m3 = message_of("mtcal-pos-ctl.dat", "TGT\x1b[2J_DATA[0]=0\n");
  EXPECT_EQ(m3.find('\x1b'), std::string::npos) << m3;
  EXPECT_NE(m3.find("\\x1b"), std::string::npos) << m3;
  const std::string m4 = message_of("mtcal-pos-unit.dat", "UNIT=\x1b]0;owned\x07\nTGT_DATA[0]=0\n");
  EXPECT_EQ(m4.find('\x1b'), std::string::npos) << m4;
  EXPECT_NE(m4.find("unit name"), std::string::npos) << m4;
  // Nine digits are still an index.
  const auto ok =
      read_positioning_dat(write_temp("mtcal-pos-9.dat", "TGT_DATA[999999999]=5\nREF_DATA_FWD[999999999,0]=1\n"));
  ASSERT_EQ(ok.targets.size(), 1u);
  EXPECT_DOUBLE_EQ(ok.targets[0], 5.0);
}

TEST(Printable, EscapesControlBytesAndCuts) {
  EXPECT_EQ(printable("abc"), "abc");
  EXPECT_EQ(printable("a\nb"), "a\\x0ab");
  EXPECT_EQ(printable(std::string(100, 'x'), 10), std::string(10, 'x') + "\u2026");
  EXPECT_EQ(printable("\x01\x02\x03", 9), "\\x01\\x02\u2026");
}

TEST(EvaluationFiles, ComparisonKeepsItsSource) {
  const auto d = parse_comparison_csv("method,test,parameter,value\nA,1,P,1\nB,1,P,2\n", "t.csv");
  EXPECT_EQ(d.source, "t.csv");
  EXPECT_EQ(compare_methods(d).source, "t.csv");
  const auto w = error_at([] { parse_comparison_csv("method,test,parameter,value\nA,1,P,x\n", "t.csv"); });
  EXPECT_EQ(w.file, "t.csv");
  EXPECT_EQ(w.line, 2);
  EXPECT_EQ(w.field, "value");
}

// The error-stream CSV, formatted in parallel slices with std::to_chars, against printf's "%.12g"
// of the user-unit value (what the writer printed before, through to_user_units) and "%.9e" of the
// errors: the same bytes for awkward values (negative zero, subnormal, huge, exact ties) and
// across the slices of a chunk of 20,000 rows.
TEST(ErrorStreamCsvTest, RowsArePrintfsTextInOrder) {
  const Machine m = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/hu40t-wCBXfYZt.yaml");
  const std::size_t n = m.axes.size(), rows = 20000;
  const double awkward[] = {0.0, -0.0, 1e-310, -2.5e-7, 123456789012345.0, 0.1 + 0.2, 1.0 / 3.0, -1e300, 5e-324};
  std::vector<double> q(rows * n), e(rows * 6);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t k = 0; k < n; ++k)
      q[r * n + k] = r < 9 ? awkward[(r + k) % 9] : std::sin(0.37 * static_cast<double>(r * n + k)) * 300.0;
    for (std::size_t c = 0; c < 6; ++c)
      e[r * 6 + c] = r < 9 ? awkward[(r + c + 3) % 9] : std::cos(1.3 * static_cast<double>(r * 6 + c)) * 1e-3;
  }
  const std::string path = (std::filesystem::temp_directory_path() / "mtcal-error-stream.csv").string();
  {
    ErrorStreamCsv csv(path, m, false, 2);
    csv.write(ErrorChunk{0, n, q, {}, e});
    csv.commit();
  }
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "C,B,X,Y,Z,dx,dy,dz,rx,ry,rz");
  char buf[64];
  for (std::size_t r = 0; r < rows; ++r) {
    ASSERT_TRUE(std::getline(in, line)) << r;
    std::string want;
    for (std::size_t k = 0; k < n; ++k) {
      std::snprintf(buf, sizeof buf, "%s%.12g", k ? "," : "", to_user_units(m.axes[k], q[r * n + k]));
      want += buf;
    }
    for (std::size_t c = 0; c < 6; ++c) {
      std::snprintf(buf, sizeof buf, ",%.9e", e[r * 6 + c]);
      want += buf;
    }
    ASSERT_EQ(line, want) << "row " << r;
  }
  EXPECT_FALSE(std::getline(in, line));
  std::filesystem::remove(path);
}
