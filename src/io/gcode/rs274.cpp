#include "mtcal/io/gcode/rs274.hpp"
#include "mtcal/util/units.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/io/system/process.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

constexpr double kFullCircle = 2 * std::numbers::pi;
constexpr std::size_t kMaxKeptWarnings = 100;
// The interpreter prints 4 decimals (saicanon.cc "%.4f"): 0.00005 in is 1.3 um. An arc's end may
// be off its circle by the rounding of the numbers printed, and more by the interpreter's own
// tolerance for arcs (LinuxCNC: 0.002 in / 0.05 mm), which it has checked already.
constexpr double kArcRadiusSlack = 0.06;  // mm

// A private temporary folder, removed with what is in it.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string tmpl = std::string(base && *base ? base : "/tmp") + "/mtcal-rs274-XXXXXX";
    if (!mkdtemp(tmpl.data()))
      throw Error(fmt::format("cannot make a temporary folder {}: {}", tmpl, std::strerror(errno)));
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw Error(fmt::format("cannot write the temporary file {}", path));
}

std::string inches(double mm) { return fmt::format("{:.10g}", mm / kMmPerInch); }

// The setup as LinuxCNC's tool table (LinuxCNC documentation, "Tool Table Format") in inches.
std::string tool_table_text(const GcodeSetup& setup) {
  std::string t;
  int pocket = 0;
  for (const auto& [number, tool] : setup.tools) {
    t += fmt::format("T{} P{}", number, ++pocket);
    for (std::size_t s = 0; s < 6; ++s)
      if (tool.offset[s] != 0)
        t += fmt::format(" {}{}", kGcodeAxes[s],
                         s < 3 ? inches(tool.offset[s]) : fmt::format("{:.10g}", tool.offset[s]));
    if (tool.diameter != 0) t += " D" + inches(tool.diameter);
    t += "\n";
  }
  return t;
}

// The setup as LinuxCNC's parameter file in inches: G28 (5161-), G30 (5181-), the coordinate
// system in effect (5220) and the nine work offsets (5221-, 20 apart).
std::string parameter_text(const GcodeSetup& setup) {
  std::string t;
  auto put = [&](int first, const GcodePosition& p) {
    for (std::size_t s = 0; s < 6; ++s)
      t += fmt::format("{} {}\n", first + static_cast<int>(s), s < 3 ? inches(p[s]) : fmt::format("{:.10g}", p[s]));
  };
  put(5161, setup.g28);
  put(5181, setup.g30);
  t += fmt::format("5220 {}\n", setup.work_system + 1);
  for (int k = 0; k < 9; ++k) put(5221 + 20 * k, setup.work_offsets[static_cast<std::size_t>(k)]);
  return t;
}

bool is_space_or_tab(char c) { return c == ' ' || c == '\t' || c == '\r'; }

}  // namespace

std::string find_rs274(const std::string& executable) {
  if (executable.empty()) return {};
  return find_program({executable}).value_or("");
}

std::string number_gcode_lines(std::string_view text) {
  std::string out;
  out.reserve(text.size() + text.size() / 4);
  std::size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    const auto nl = text.find('\n', pos);
    const std::string_view row = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    ++line;
    std::size_t i = 0;
    while (i < row.size() && (is_space_or_tab(row[i]) || row[i] == '/')) ++i;
    if (i < row.size() && row[i] == '%') {
      out += row;
    } else {
      std::size_t rest = i;
      if (rest < row.size() && (row[rest] == 'N' || row[rest] == 'n')) {
        std::size_t k = rest + 1;
        while (k < row.size() && is_space_or_tab(row[k])) ++k;
        const std::size_t digits = k;
        while (k < row.size() && row[k] >= '0' && row[k] <= '9') ++k;
        if (k > digits) rest = k;
      }
      out += row.substr(0, i);
      out += fmt::format("N{} ", line);
      out += row.substr(rest);
    }
    if (nl != std::string_view::npos) out += '\n';
  }
  return out;
}

Rs274Output run_rs274(const std::string& program_path, const GcodeSetup& setup, const Rs274Options& options) {
  const std::string exe = find_rs274(options.executable);
  if (exe.empty())
    throw Error(
        fmt::format("LinuxCNC's interpreter '{}' is not installed (Debian package linuxcnc-uspace: "
                    "apt-get install linuxcnc-uspace)",
                    options.executable));
  const std::string text = read_text_file(program_path, "G-code program");
  TempDir tmp;
  const std::filesystem::path program(program_path);
  const std::string copy = tmp.path() + "/" + program.filename().string();
  write_file(copy, number_gcode_lines(text));
  write_file(tmp.path() + "/tools.tbl", tool_table_text(setup));
  write_file(tmp.path() + "/parameters.var", parameter_text(setup));
  std::error_code ec;
  std::string dir = std::filesystem::absolute(program, ec).parent_path().string();
  if (ec || dir.empty()) dir = ".";
  // HOME is the temporary folder: LinuxCNC 2.9 keeps the loaded tool table in $HOME/.tool.mmap
  // (tooldata_mmap.cc), one file shared by every interpreter and controller the user runs, so two
  // programs interpreted at once (or a running LinuxCNC) would see each other's tools.
  const ProgramRun r =
      run_program({exe, "-g", "-t", tmp.path() + "/tools.tbl", "-v", tmp.path() + "/parameters.var", copy},
                  options.timeout, options.max_output, dir, {"HOME=" + tmp.path()});
  if (r.timed_out) throw Error(fmt::format("{} was stopped after {} s on {}", exe, options.timeout, program_path));
  if (r.signal != 0) throw Error(fmt::format("{} stopped by signal {} on {}", exe, r.signal, program_path));
  if (r.out.size() >= options.max_output)
    throw Error(fmt::format("{} printed more than {} for {}", exe,
                            format_bytes(static_cast<double>(options.max_output)), program_path));
  Rs274Output out;
  out.calls = r.out;
  if (r.exit_status == 0) return out;
  // The interpreter's error: "executing", its message, the line's text (ours: "N<line> ...").
  std::vector<std::string> rows;
  std::size_t pos = 0;
  while (pos < r.err.size()) {
    const auto nl = r.err.find('\n', pos);
    std::string row = r.err.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
    pos = nl == std::string::npos ? r.err.size() : nl + 1;
    while (!row.empty() && (row.back() == '\r' || row.back() == ' ')) row.pop_back();
    if (!row.empty() && row != "executing") rows.push_back(row);
  }
  std::string message = rows.empty() ? fmt::format("exit status {}", r.exit_status) : rows.front();
  int line = 0;
  std::string source_text;
  if (rows.size() >= 2) {
    std::string_view t = rows[1];
    std::size_t i = 0;
    while (i < t.size() && (is_space_or_tab(t[i]) || t[i] == '/')) ++i;
    if (i < t.size() && (t[i] == 'N' || t[i] == 'n')) {
      std::size_t k = i + 1;
      const auto [end, ec2] = std::from_chars(t.data() + k, t.data() + t.size(), line);
      if (ec2 != std::errc()) line = 0;
      k = static_cast<std::size_t>(end - t.data());
      if (k < t.size() && t[k] == ' ') ++k;
      source_text = std::string(t.substr(0, i)) + std::string(t.substr(k));
    } else {
      source_text = std::string(t);
    }
  }
  if (message == "File ended with no percent sign or program end") {
    out.missing_end = true;
    return out;
  }
  throw InputError({program_path, line, ""},
                   fmt::format("LinuxCNC's interpreter stopped: {}{}", message,
                               source_text.empty() ? "" : fmt::format(" (in '{}')", printable(source_text, 80))));
}

CanonReader::CanonReader(std::string_view calls, std::string source, GcodeOptions options)
    : text_(calls), source_(std::move(source)), options_(std::move(options)) {
  position_ = options_.start;
}

void CanonReader::fail(const std::string& what) const {
  throw InputError({source_, line_, ""}, fmt::format("(call {} of LinuxCNC's interpreter) {}", row_, what));
}

void CanonReader::warn(const std::string& what) {
  ++counts_.warnings;
  if (warnings_.size() < kMaxKeptWarnings) warnings_.push_back(fmt::format("{}:{}: {}", source_, line_, what));
}

bool CanonReader::next(GcodeMove& move) {
  while (pos_ < text_.size()) {
    const auto nl = text_.find('\n', pos_);
    std::string_view row = text_.substr(pos_, nl == std::string_view::npos ? std::string_view::npos : nl - pos_);
    pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
    ++row_;
    ++counts_.lines;
    while (!row.empty() && (is_space_or_tab(row.back()))) row.remove_suffix(1);
    std::size_t i = 0;
    while (i < row.size() && is_space_or_tab(row[i])) ++i;
    if (i == row.size()) continue;
    // "<count> N<line>|N..... NAME(args)" (saicanon.cc: PRINTn, print_nc_line_number).
    const std::size_t count_begin = i;
    while (i < row.size() && row[i] >= '0' && row[i] <= '9') ++i;
    if (i == count_begin || i == row.size() || !is_space_or_tab(row[i]))
      fail(fmt::format("expected a call's number at the start of the line, found '{}'", printable(row)));
    while (i < row.size() && is_space_or_tab(row[i])) ++i;
    line_ = 0;
    if (i < row.size() && row[i] == 'N') {
      ++i;
      if (row.substr(i, 5) == ".....") {
        i += 5;
      } else {
        const std::size_t d = i;
        while (i < row.size() && row[i] >= '0' && row[i] <= '9') ++i;
        if (i == d)
          fail(fmt::format("expected a line number or '.....' after 'N', found '{}'", printable(row.substr(d))));
        const auto [p, ec] = std::from_chars(row.data() + d, row.data() + i, line_);
        if (ec != std::errc()) line_ = 0;
      }
      while (i < row.size() && is_space_or_tab(row[i])) ++i;
    }
    const std::size_t name_begin = i;
    while (i < row.size() && ((row[i] >= 'A' && row[i] <= 'Z') || row[i] == '_' || (row[i] >= '0' && row[i] <= '9')))
      ++i;
    const std::string name(row.substr(name_begin, i - name_begin));
    if (name.empty() || i == row.size() || row[i] != '(' || row.back() != ')')
      fail(fmt::format("expected a canonical call NAME(arguments), found '{}'", printable(row.substr(name_begin))));
    ++counts_.blocks;
    const std::string_view args_text = row.substr(i + 1, row.size() - i - 2);
    // Arguments: numbers and names, apart by commas or blanks.
    std::vector<std::string_view> args;
    {
      std::size_t k = 0;
      while (k < args_text.size()) {
        if (args_text[k] == ',' || is_space_or_tab(args_text[k])) {
          ++k;
          continue;
        }
        std::size_t e = k;
        while (e < args_text.size() && args_text[e] != ',' && !is_space_or_tab(args_text[e])) ++e;
        args.push_back(args_text.substr(k, e - k));
        k = e;
      }
    }
    auto number = [&](std::size_t k) {
      if (k >= args.size()) fail(fmt::format("{} with {} arguments (expected at least {})", name, args.size(), k + 1));
      double v = 0;
      std::string_view a = args[k];
      const auto [p, ec] = std::from_chars(a.data(), a.data() + a.size(), v);
      if (ec != std::errc() || p != a.data() + a.size() || !std::isfinite(v))
        fail(fmt::format("expected a number as argument {} of {}, found '{}'", k + 1, name, printable(a, 20)));
      return v;
    };
    auto expect_args = [&](std::initializer_list<std::size_t> allowed) {
      for (std::size_t n : allowed)
        if (args.size() == n) return;
      std::string expected;
      for (std::size_t n : allowed) expected += (expected.empty() ? "" : " or ") + std::to_string(n);
      fail(fmt::format("{} with {} arguments (expected {})", name, args.size(), expected));
    };
    const double scale = inches_ ? kMmPerInch : 1.0;
    // Six numbers X Y Z A B C (program units and deg) from argument `first` on.
    auto xyzabc = [&](std::size_t first) {
      GcodePosition p{};
      for (std::size_t s = 0; s < 6; ++s) p[s] = s < 3 ? number(first + s) * scale : number(first + s);
      return p;
    };
    auto no_uvw = [&](std::size_t first) {
      for (std::size_t k = first; k < args.size(); ++k)
        if (number(k) != 0) fail(fmt::format("{} moves U, V or W: mtcal simulates the axes X Y Z A B C only", name));
    };
    auto shift = [&](std::size_t s) { return g5x_[s] + g92_[s] + length_[s]; };
    auto to_frame = [&](const GcodePosition& program) {
      GcodePosition p{};
      for (std::size_t s = 0; s < 6; ++s) p[s] = program[s] + shift(s);
      return p;
    };
    auto begin_move = [&](GcodeMotion motion) {
      move = GcodeMove{};
      move.motion = motion;
      move.plane = plane_;
      move.line = line_;
      move.feed = feed_;
      move.tool = tool_;
      move.spindle = spindle_;
      move.start = position_;
    };
    auto check_axes = [&](const GcodePosition& end) {
      for (std::size_t s = 0; s < 6; ++s)
        if (end[s] != position_[s] && options_.axes.find(kGcodeAxes[s]) == std::string::npos &&
            options_.axes.find(static_cast<char>(kGcodeAxes[s] - 'A' + 'a')) == std::string::npos)
          fail(fmt::format("{} moves {}, an axis this machine does not have (its axes: {})", name, kGcodeAxes[s],
                           options_.axes));
    };

    if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED") {
      expect_args({6, 9});
      no_uvw(6);
      const GcodePosition end = to_frame(xyzabc(0));
      check_axes(end);
      begin_move(name == "STRAIGHT_FEED" ? GcodeMotion::Linear : GcodeMotion::Rapid);
      move.end = end;
      position_ = end;
      ++counts_.moves;
      return true;
    }
    if (name == "ARC_FEED") {
      // ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end_point, a, b, c
      // [, u, v, w]) in the plane selected (saicanon.cc): first/second are X/Y (G17), Y/Z (G19),
      // Z/X (G18); rotation > 0 turns counter-clockwise, |rotation| - 1 further full turns.
      expect_args({9, 12});
      no_uvw(9);
      const PlaneAxes pa = plane_axes(plane_);
      const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v),
                 w = static_cast<std::size_t>(pa.w);
      GcodePosition program{};
      program[u] = number(0) * scale;
      program[v] = number(1) * scale;
      program[w] = number(5) * scale;
      for (std::size_t s = 3; s < 6; ++s) program[s] = number(3 + s);
      const double rotation = number(4);
      if (rotation == 0 || rotation != std::floor(rotation))
        fail(fmt::format("ARC_FEED with rotation {} (expected a whole number other than 0)", rotation));
      const GcodePosition end = to_frame(program);
      check_axes(end);
      begin_move(rotation > 0 ? GcodeMotion::ArcCCW : GcodeMotion::ArcCW);
      move.end = end;
      const double cu = number(2) * scale + shift(u), cv = number(3) * scale + shift(v);
      move.centre[u] = cu;
      move.centre[v] = cv;
      move.centre[w] = position_[w];
      const double su = position_[u], sv = position_[v], eu = end[u], ev = end[v];
      const double r0 = std::hypot(su - cu, sv - cv), r1 = std::hypot(eu - cu, ev - cv);
      if (r0 <= 1e-9 && r1 <= 1e-9) {
        // A helix of radius 0 (cutter compensation of a hole as wide as the tool): a straight
        // feed along the plane's normal, exactly.
        move.motion = GcodeMotion::Linear;
        move.centre = {};
        position_ = end;
        ++counts_.moves;
        return true;
      }
      if (!(r0 > 1e-9)) fail("ARC_FEED whose centre is its start point (expected a radius > 0)");
      if (std::abs(r0 - r1) > kArcRadiusSlack + 1e-3 * std::max(r0, r1))
        fail(
            fmt::format("ARC_FEED with start radius {:.6g} mm and end radius {:.6g} mm (expected the end on the "
                        "circle)",
                        r0, r1));
      const bool ccw = rotation > 0;
      const double a =
          std::atan2((su - cu) * (ev - cv) - (sv - cv) * (eu - cu), (su - cu) * (eu - cu) + (sv - cv) * (ev - cv));
      double sweep = std::hypot(eu - su, ev - sv) <= 1e-7
                         ? (ccw ? kFullCircle : -kFullCircle)
                         : (ccw ? (a <= 0 ? a + kFullCircle : a) : (a >= 0 ? a - kFullCircle : a));
      const double turns = std::abs(rotation) - 1;
      if (turns > 1e6) fail(fmt::format("ARC_FEED with {} turns", turns));
      if (std::hypot(eu - su, ev - sv) > 1e-7) sweep += (ccw ? 1 : -1) * kFullCircle * turns;
      move.sweep = sweep;
      position_ = end;
      ++counts_.moves;
      return true;
    }
    if (name == "USE_LENGTH_UNITS") {
      expect_args({1});
      if (args[0] == "CANON_UNITS_INCHES")
        inches_ = true;
      else if (args[0] == "CANON_UNITS_MM")
        inches_ = false;
      else
        fail(fmt::format("USE_LENGTH_UNITS({}) (expected CANON_UNITS_MM or CANON_UNITS_INCHES)",
                         printable(args[0], 30)));
    } else if (name == "SELECT_PLANE") {
      expect_args({1});
      if (args[0] == "CANON_PLANE_XY")
        plane_ = GcodePlane::XY;
      else if (args[0] == "CANON_PLANE_YZ")
        plane_ = GcodePlane::YZ;
      else if (args[0] == "CANON_PLANE_XZ")
        plane_ = GcodePlane::ZX;
      else
        fail(fmt::format("SELECT_PLANE({}): mtcal simulates the planes XY, YZ and XZ", printable(args[0], 30)));
    } else if (name == "SET_G5X_OFFSET") {
      expect_args({7, 10});
      no_uvw(7);
      g5x_ = xyzabc(1);
    } else if (name == "SET_G92_OFFSET" || name == "SET_ORIGIN_OFFSETS") {
      expect_args({6, 9});
      no_uvw(6);
      g92_ = xyzabc(0);
    } else if (name == "USE_TOOL_LENGTH_OFFSET") {
      // (x y z, a b c, u v w) in program units: the tool's offsets the interpreter applies.
      expect_args({9, 2});
      if (args.size() == 2) {
        length_ = {};
        length_[0] = number(0) * scale;
        length_[2] = number(1) * scale;
      } else {
        no_uvw(6);
        length_ = xyzabc(0);
      }
    } else if (name == "SET_XY_ROTATION") {
      expect_args({1});
      if (number(0) != 0)
        fail(fmt::format("SET_XY_ROTATION({}): a rotated coordinate system (G10 L2 R) is not simulated", number(0)));
    } else if (name == "SET_FEED_RATE") {
      expect_args({1});
      feed_ = number(0) * scale;
    } else if (name == "CHANGE_TOOL") {
      expect_args({1});
      tool_ = static_cast<int>(number(0));
      ++counts_.tool_changes;
    } else if (name == "SET_SPINDLE_SPEED") {
      expect_args({1, 2});
      spindle_ = number(args.size() - 1);
      ++counts_.s_words;
    } else if (name == "STRAIGHT_PROBE") {
      fail("STRAIGHT_PROBE: probing (G38), whose path depends on where the probe trips, cannot be simulated");
    } else if (name == "START_SPEED_FEED_SYNCH" || name == "START_SPEED_FEED_SYNC") {
      fail(fmt::format("{}: motion synchronised with the spindle (G33 or G76 threading, lathe work) is not simulated",
                       name));
    } else if (name == "RIGID_TAP") {
      fail("RIGID_TAP: rigid tapping (G33.1) follows the spindle and is not simulated");
    } else if (name == "NURBS_FEED" || name == "NURBS_G5_FEED" || name == "NURBS_G6_FEED" || name == "SPLINE_FEED") {
      fail(fmt::format("{}: spline motion (G5, G5.1, G5.2) is not simulated", name));
    } else {
      // Calls that move nothing (saicanon.cc): comments, spindle, coolant, modes, tool selection.
      static constexpr const char* kStill[] = {"COMMENT",
                                               "MESSAGE",
                                               "LOG",
                                               "LOGOPEN",
                                               "LOGAPPEND",
                                               "LOGCLOSE",
                                               "SET_FEED_MODE",
                                               "SET_FEED_REFERENCE",
                                               "SET_MOTION_CONTROL_MODE",
                                               "SET_NAIVECAM_TOLERANCE",
                                               "SET_TRAVERSE_RATE",
                                               "FLOOD_ON",
                                               "FLOOD_OFF",
                                               "MIST_ON",
                                               "MIST_OFF",
                                               "START_SPINDLE_CLOCKWISE",
                                               "START_SPINDLE_COUNTERCLOCKWISE",
                                               "STOP_SPINDLE_TURNING",
                                               "SET_SPINDLE_MODE",
                                               "ORIENT_SPINDLE",
                                               "SPINDLE_RETRACT",
                                               "SPINDLE_RETRACT_TRAVERSE",
                                               "SELECT_TOOL",
                                               "START_CHANGE",
                                               "CHANGE_TOOL_NUMBER",
                                               "ON_RESET",
                                               "PROGRAM_END",
                                               "PROGRAM_STOP",
                                               "OPTIONAL_PROGRAM_STOP",
                                               "PALLET_SHUTTLE",
                                               "DWELL",
                                               "ENABLE_FEED_OVERRIDE",
                                               "DISABLE_FEED_OVERRIDE",
                                               "ENABLE_SPEED_OVERRIDE",
                                               "DISABLE_SPEED_OVERRIDE",
                                               "ENABLE_ADAPTIVE_FEED",
                                               "DISABLE_ADAPTIVE_FEED",
                                               "ENABLE_FEED_HOLD",
                                               "DISABLE_FEED_HOLD",
                                               "SET_CUTTER_RADIUS_COMPENSATION",
                                               "START_CUTTER_RADIUS_COMPENSATION",
                                               "STOP_CUTTER_RADIUS_COMPENSATION",
                                               "STOP_SPEED_FEED_SYNCH",
                                               "CLAMP_AXIS",
                                               "UNCLAMP_AXIS",
                                               "TURN_PROBE_ON",
                                               "TURN_PROBE_OFF",
                                               "USE_NO_SPINDLE_FORCE",
                                               "SET_SPINDLE_FORCE",
                                               "FINISH",
                                               "SET_AUX_OUTPUT_BIT",
                                               "CLEAR_AUX_OUTPUT_BIT",
                                               "SET_AUX_OUTPUT_VALUE",
                                               "SET_MOTION_OUTPUT_BIT",
                                               "CLEAR_MOTION_OUTPUT_BIT",
                                               "SET_MOTION_OUTPUT_VALUE",
                                               "WAIT",
                                               "SYSTEM",
                                               "INIT_CANON",
                                               "SET_BLOCK_DELETE",
                                               "SET_OPTIONAL_PROGRAM_STOP",
                                               "USER_DEFINED_FUNCTION"};
      const bool still = std::any_of(std::begin(kStill), std::end(kStill), [&](const char* k) { return name == k; });
      if (!still) warn(fmt::format("canonical call {} is not known to mtcal and is skipped", printable(name, 40)));
      ++counts_.ignored_words;
    }
  }
  return false;
}

GcodeProgram parse_canon(std::string_view calls, const std::string& source, const GcodeOptions& options) {
  CanonReader reader(calls, source, options);
  GcodeProgram p;
  p.source = source;
  p.interpreter = "rs274";
  GcodeMove m;
  while (reader.next(m)) p.moves.push_back(m);
  p.counts = reader.counts();
  p.warnings = reader.warnings();
  return p;
}

GcodeProgram read_gcode_rs274(const std::string& path, const GcodeOptions& options, const Rs274Options& rs274) {
  refuse_lathe_program(read_text_file(path, "G-code program"), path);
  const Rs274Output out = run_rs274(path, options.setup, rs274);
  GcodeProgram p = parse_canon(out.calls, path, options);
  if (out.missing_end) {
    ++p.counts.warnings;
    p.warnings.push_back(
        fmt::format("{}: the file ends with no M2, M30 or '%' (LinuxCNC's interpreter reports it): "
                    "the moves up to its end are simulated",
                    path));
  }
  return p;
}

}  // namespace mtcal
