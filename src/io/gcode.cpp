#include "mtcal/io/gcode.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/io/files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

constexpr double kInch = 25.4;  // mm per inch, exact by definition (1959 international inch)
constexpr double kTwoPi = 2 * std::numbers::pi;
// Below this chord (mm) an I J K arc's end is its start: a full circle. Far below any machine's
// resolution, far above the rounding of incremental sums.
constexpr double kSamePoint = 1e-7;

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
char upper(char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; }

int axis_slot(char letter) {
  switch (letter) {
    case 'X': return 0;
    case 'Y': return 1;
    case 'Z': return 2;
    case 'A': return 3;
    case 'B': return 4;
    case 'C': return 5;
    default: return -1;
  }
}

// What a character looks like in a message: itself if printable, else its code.
std::string shown(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x21 && u < 0x7f) return fmt::format("'{}'", c);
  return fmt::format("byte 0x{:02x}", u);
}

std::string fmt_mm(double v) { return fmt::format("{:.6g}", v); }

}  // namespace

GcodeReader::GcodeReader(std::string_view text, std::string source, GcodeOptions options)
    : text_(text), source_(std::move(source)), options_(std::move(options)) {
  for (char c : options_.axes) {
    const char u = upper(c);
    if (axis_slot(u) < 0)
      throw InputError({source_, 0, ""}, fmt::format("machine axis letters must be among XYZABC, found {}", shown(c)));
    allowed_[static_cast<std::size_t>(u - 'A')] = true;
  }
  position_ = options_.start;
  words_.reserve(16);
}

void GcodeReader::fail(int column, const std::string& what) const {
  throw InputError({source_, line_, ""}, fmt::format("column {}: {}", column, what));
}

bool GcodeReader::read_block() {
  words_.clear();
  while (pos_ < text_.size()) {
    const char* const base = text_.data();
    const std::size_t line_start = pos_;
    const void* nl = std::memchr(base + pos_, '\n', text_.size() - pos_);
    const std::size_t line_end = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - base) : text_.size();
    pos_ = nl ? line_end + 1 : text_.size();
    ++line_;
    ++counts_.lines;
    std::size_t i = line_start;
    auto column = [&](std::size_t at) { return static_cast<int>(at - line_start) + 1; };
    while (i < line_end) {
      const char c = base[i];
      if (is_blank(c)) {
        ++i;
        continue;
      }
      if (c == ';') break;
      if (c == '(') {
        const void* close = std::memchr(base + i, ')', line_end - i);
        if (!close) fail(column(i), "unterminated comment: expected ')' before the end of the line");
        i = static_cast<std::size_t>(static_cast<const char*>(close) - base) + 1;
        continue;
      }
      if (c == '%') {
        // RS274NGC's program markers: one before the first block, one after the last.
        if (!words_.empty()) fail(column(i), "'%' must be alone on its line (the program's start or end marker)");
        for (std::size_t k = i + 1; k < line_end; ++k)
          if (!is_blank(base[k]))
            fail(column(k), fmt::format("expected nothing after '%' on its line, found {}", shown(base[k])));
        if (closed_) fail(column(i), "a second closing '%' (expected the end of the program)");
        if (!opened_ && counts_.blocks == 0)
          opened_ = true;
        else
          closed_ = true;
        i = line_end;
        continue;
      }
      if (!is_letter(c)) fail(column(i), fmt::format("expected a word (a letter and a number), found {}", shown(c)));
      if (closed_) fail(column(i), "a word after the closing '%' (expected the end of the program)");
      const char letter = upper(c);
      const int col = column(i);
      if (!std::strchr("GMSTNFXYZABCIJKR", letter))
        fail(col,
             fmt::format("unsupported word '{}' (expected G, M, S, T, N, F, X, Y, Z, A, B, C, I, J, K or R)", letter));
      if (axis_slot(letter) >= 0 && !allowed_[static_cast<std::size_t>(letter - 'A')])
        fail(col, fmt::format("axis word '{}' for an axis this machine does not have (its axes: {})", letter,
                              options_.axes));
      ++i;
      while (i < line_end && is_blank(base[i])) ++i;
      // The number: [+-] digits [. digits] or [+-] . digits; no exponent, as in RS274NGC.
      const std::size_t num = i;
      std::size_t k = i;
      if (k < line_end && (base[k] == '+' || base[k] == '-')) ++k;
      const std::size_t mantissa = k;
      std::size_t digits = 0;
      while (k < line_end && is_digit(base[k])) ++k, ++digits;
      if (k < line_end && base[k] == '.') {
        ++k;
        while (k < line_end && is_digit(base[k])) ++k, ++digits;
      }
      if (digits == 0) {
        std::size_t e = num;
        while (e < line_end && e - num < 12 && !is_blank(base[e]) && base[e] != '(' && base[e] != ';') ++e;
        fail(col, fmt::format("expected a number after '{}', found {}", letter,
                              e == num ? std::string("the end of the block")
                                       : "'" + std::string(base + num, e - num) + "'"));
      }
      if (k < line_end && (base[k] == 'e' || base[k] == 'E') && k + 1 < line_end &&
          (is_digit(base[k + 1]) || base[k + 1] == '+' || base[k + 1] == '-'))
        fail(col, fmt::format("expected a G-code number after '{}' (no exponent), found '{}'", letter,
                              std::string(base + num, k + 2 - num)));
      double v = 0;
      // from_chars takes no '+'; a '-' it takes itself.
      const char* first = base[num] == '+' ? base + mantissa : base + num;
      const auto [end, ec] = std::from_chars(first, base + k, v, std::chars_format::fixed);
      if (ec != std::errc() || end != base + k || !std::isfinite(v))
        fail(col,
             fmt::format("expected a finite number after '{}', found '{}'", letter, std::string(base + num, k - num)));
      words_.push_back({letter, v, col, static_cast<int>(k - line_start) + 1 - col});
      i = k;
    }
    if (!words_.empty()) {
      block_begin_ = line_start;
      block_end_ = line_end;
      ++counts_.blocks;
      return true;
    }
  }
  return false;
}

bool GcodeReader::next(GcodeMove& move) {
  while (read_block())
    if (apply_block(move)) return true;
  return false;
}

bool GcodeReader::next_block(GcodeMove& move, bool& moved) {
  if (!read_block()) return false;
  moved = apply_block(move);
  return true;
}

bool GcodeReader::apply_block(GcodeMove& move) {
  int motion = -1, motion_col = 0;
  int plane = -1, plane_col = 0, units = -1, units_col = 0, distance = -1, distance_col = 0;
  std::int64_t n = -1;
  int n_col = 0, f_col = 0, r_col = 0;
  double feed = -1, r = 0;
  std::array<double, 6> axis{};
  std::array<int, 6> axis_col{};  // 0: not in the block
  std::array<double, 3> ijk{};
  std::array<int, 3> ijk_col{};
  int first_axis_col = 0, first_arc_col = 0;

  auto once = [&](int& seen_col, const Word& w) {
    if (seen_col) fail(w.column, fmt::format("'{}' given twice in one block (first at column {})", w.letter, seen_col));
    seen_col = w.column;
  };
  auto group = [&](int& value, int& col, int code, const Word& w, const char* what) {
    if (col) fail(w.column, fmt::format("two {} codes in one block: G{} at column {} and G{}", what, value, col, code));
    value = code;
    col = w.column;
  };

  for (const Word& w : words_) {
    switch (w.letter) {
      case 'G': {
        const double code = w.value;
        if (!(code >= 0 && code <= 999 && code == std::floor(code)))
          fail(w.column, fmt::format("unsupported G code G{} (expected G0 G1 G2 G3 G17 G18 G19 G20 G21 G90 G91, or the "
                                     "ignored G40 G49 G80 G94)",
                                     code));
        const int g = static_cast<int>(code);
        switch (g) {
          case 0:
          case 1:
          case 2:
          case 3: group(motion, motion_col, g, w, "motion"); break;
          case 17:
          case 18:
          case 19: group(plane, plane_col, g, w, "plane"); break;
          case 20:
          case 21: group(units, units_col, g, w, "unit"); break;
          case 90:
          case 91: group(distance, distance_col, g, w, "distance mode"); break;
          // Cutter radius and tool length compensation off, canned cycle off, feed per minute:
          // the states this reader assumes anyway.
          case 40:
          case 49:
          case 80:
          case 94: ++counts_.ignored_words; break;
          default:
            fail(w.column, fmt::format("unsupported G code G{} (expected G0 G1 G2 G3 G17 G18 G19 G20 G21 G90 G91, or "
                                       "the ignored G40 G49 G80 G94)",
                                       g));
        }
        break;
      }
      case 'M':
      case 'S':
      case 'T': ++counts_.ignored_words; break;
      case 'N':
        once(n_col, w);
        if (!(w.value >= 0 && w.value == std::floor(w.value) && w.value < 1e15))
          fail(w.column, fmt::format("expected a whole block number >= 0 after 'N', found {}", w.value));
        n = static_cast<std::int64_t>(w.value);
        break;
      case 'F':
        once(f_col, w);
        if (w.value < 0) fail(w.column, fmt::format("expected a feed >= 0 after 'F', found {}", w.value));
        feed = w.value;
        break;
      case 'R':
        once(r_col, w);
        r = w.value;
        if (!first_arc_col) first_arc_col = w.column;
        break;
      case 'I':
      case 'J':
      case 'K': {
        const auto s = static_cast<std::size_t>(w.letter - 'I');
        once(ijk_col[s], w);
        ijk[s] = w.value;
        if (!first_arc_col) first_arc_col = w.column;
        break;
      }
      default: {
        const auto s = static_cast<std::size_t>(axis_slot(w.letter));
        once(axis_col[s], w);
        axis[s] = w.value;
        if (!first_axis_col) first_axis_col = w.column;
      }
    }
  }

  // Modes first (RS274NGC order of execution): G20 X1 is one inch, G91 X1 is a step.
  if (units >= 0) inches_ = units == 20;
  if (distance >= 0) incremental_ = distance == 91;
  if (plane >= 0) plane_ = plane == 17 ? GcodePlane::XY : plane == 18 ? GcodePlane::ZX : GcodePlane::YZ;
  const double scale = inches_ ? kInch : 1.0;
  if (feed >= 0) feed_ = feed * scale;
  if (motion >= 0) motion_ = motion;

  const bool has_ijk = ijk_col[0] || ijk_col[1] || ijk_col[2];
  if ((has_ijk || r_col) && motion_ != 2 && motion_ != 3)
    fail(first_arc_col, fmt::format("I, J, K and R go with G2 or G3, found them with {}",
                                    motion_ < 0 ? std::string("no motion mode") : fmt::format("G{}", motion_)));
  if (has_ijk && r_col) {
    const int ijk_first = *std::min_element(ijk_col.begin(), ijk_col.end(),
                                            [](int a, int b) { return (a ? a : 1 << 30) < (b ? b : 1 << 30); });
    fail(std::max(r_col, ijk_first), "R and I/J/K in one block (expected the arc's centre one way: I J K or R)");
  }
  if (first_axis_col && motion_ < 0)
    fail(first_axis_col,
         "axis word with no motion mode in effect (expected G0, G1, G2 or G3 in this or an earlier block)");

  const bool arc = motion_ == 2 || motion_ == 3;
  if (!first_axis_col && !(arc && (has_ijk || r_col))) return false;

  GcodePosition end = position_;
  for (std::size_t s = 0; s < 6; ++s) {
    if (!axis_col[s]) continue;
    const double v = s < 3 ? axis[s] * scale : axis[s];  // A B C stay in degrees
    end[s] = incremental_ ? position_[s] + v : v;
    if (!std::isfinite(end[s])) fail(axis_col[s], fmt::format("the position of {} is not finite", kGcodeAxes[s]));
  }

  move.motion = static_cast<GcodeMotion>(motion_);
  move.plane = plane_;
  move.line = line_;
  move.n = n;
  move.feed = feed_;
  move.start = position_;
  move.end = end;
  move.centre = {};
  move.sweep = 0;

  if (arc) {
    const PlaneAxes pa = plane_axes(plane_);
    const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v),
               w = static_cast<std::size_t>(pa.w);
    const int at = motion_col ? motion_col : (first_axis_col ? first_axis_col : first_arc_col);
    if (!has_ijk && !r_col) fail(at, fmt::format("arc (G{}) with no centre (expected I J K offsets or R)", motion_));
    const double su = position_[u], sv = position_[v], eu = end[u], ev = end[v];
    const double chord = std::hypot(eu - su, ev - sv);
    const bool ccw = motion_ == 3;
    double cu = 0, cv = 0;
    if (has_ijk) {
      // RS274NGC: I J K are offsets of the centre from the start along X Y Z, whatever G90/G91.
      if (ijk_col[w])
        fail(ijk_col[w],
             fmt::format("'{}' is no centre offset in the {} plane (expected {} and {})", static_cast<char>('I' + w),
                         to_string(plane_), static_cast<char>('I' + u), static_cast<char>('I' + v)));
      if (!ijk_col[u] && !ijk_col[v])
        fail(at, fmt::format("arc (G{}) with no centre in the {} plane (expected {} or {})", motion_, to_string(plane_),
                             static_cast<char>('I' + u), static_cast<char>('I' + v)));
      cu = su + ijk[u] * scale;
      cv = sv + ijk[v] * scale;
      const double r0 = std::hypot(su - cu, sv - cv), r1 = std::hypot(eu - cu, ev - cv);
      if (!(r0 > kSamePoint)) fail(first_arc_col, "the arc's centre is its start point (expected a radius > 0)");
      const double tol = std::max(kArcRadiusTolerance, kArcRadiusRelative * std::max(r0, r1));
      if (!(std::abs(r0 - r1) <= tol))
        fail(first_arc_col, fmt::format("the arc's start radius {} mm and end radius {} mm differ by {} mm (expected "
                                        "the end on the circle, within {} mm)",
                                        fmt_mm(r0), fmt_mm(r1), fmt_mm(std::abs(r0 - r1)), fmt_mm(tol)));
      double sweep = 0;
      if (chord <= kSamePoint) {
        sweep = ccw ? kTwoPi : -kTwoPi;
      } else {
        const double a =
            std::atan2((su - cu) * (ev - cv) - (sv - cv) * (eu - cu), (su - cu) * (eu - cu) + (sv - cv) * (ev - cv));
        sweep = ccw ? (a <= 0 ? a + kTwoPi : a) : (a >= 0 ? a - kTwoPi : a);
      }
      move.sweep = sweep;
    } else {
      // R form: the centre lies on the chord's perpendicular bisector; R > 0 takes the arc of at
      // most 180 deg, R < 0 the longer one (RS274NGC 3.5.3.1).
      const double rr = std::abs(r * scale);
      if (chord <= kSamePoint)
        fail(r_col, "an R arc whose end is its start (expected I J K for a full circle, or another end point)");
      const double half = chord / 2;
      const double tol = std::max(kArcRadiusTolerance, kArcRadiusRelative * rr);
      if (rr < half - tol)
        fail(r_col, fmt::format("R {} mm is shorter than half the chord, {} mm (expected |R| >= {} mm)", fmt_mm(rr),
                                fmt_mm(half), fmt_mm(half)));
      const double h = std::sqrt(std::max(0.0, rr * rr - half * half));
      const double nu = -(ev - sv) / chord, nv = (eu - su) / chord;  // left of the chord
      // The centre is on the left of travel for a G3 arc under 180 deg.
      const double side = (ccw ? 1.0 : -1.0) * (r < 0 ? -1.0 : 1.0);
      cu = (su + eu) / 2 + side * h * nu;
      cv = (sv + ev) / 2 + side * h * nv;
      const double small = 2 * std::asin(std::min(1.0, half / std::max(rr, half)));
      const double sweep = r < 0 ? kTwoPi - small : small;
      move.sweep = ccw ? sweep : -sweep;
    }
    move.centre[u] = cu;
    move.centre[v] = cv;
    move.centre[w] = position_[w];
  }

  position_ = end;
  ++counts_.moves;
  return true;
}

GcodeProgram parse_gcode(std::string_view text, const std::string& source, const GcodeOptions& options) {
  GcodeReader reader(text, source, options);
  GcodeProgram p;
  p.source = source;
  GcodeMove m;
  while (reader.next(m)) p.moves.push_back(m);
  p.counts = reader.counts();
  return p;
}

GcodeProgram read_gcode(const std::string& path, const GcodeOptions& options) {
  const std::string text = read_text_file(path, "G-code program");
  return parse_gcode(text, path, options);
}

}  // namespace mtcal
