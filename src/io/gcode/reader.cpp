#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
// Below this chord (mm) an I J K arc's end is its start: a full circle. Far below any machine's
// resolution, far above the rounding of incremental sums.
constexpr double kSamePoint = 1e-7;
// Warnings kept word for word; the rest are counted.
constexpr std::size_t kMaxWarnings = 100;

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
  const int ws = options_.setup.work_system;
  if (ws < 0 || ws > 8)
    throw InputError({source_, 0, ""},
                     fmt::format("the coordinate system in effect must be 0 (G54) to 8 (G59.3), found {}", ws));
  work_system_ = ws;
  work_ = options_.setup.work_offsets[static_cast<std::size_t>(ws)];
  words_.reserve(16);
}

void GcodeReader::fail(int column, const std::string& what) const {
  throw InputError({source_, line_, ""}, fmt::format("column {}: {}", column, what));
}

void GcodeReader::needs_interpreter(int column, const std::string& what) const {
  throw GcodeNeedsInterpreter(
      {source_, line_, ""},
      fmt::format("column {}: {}: RS274NGC beyond the ISO dialect of mtcal's reader (LinuxCNC's interpreter reads it)",
                  column, what));
}

void GcodeReader::lathe(int column, const std::string& what) const {
  throw GcodeLatheProgram({source_, line_, ""},
                          fmt::format("column {}: {}: a lathe program (mtcal simulates milling machines)", column,
                                      what));
}

void GcodeReader::warn(int column, const std::string& word, const std::string& why) {
  ++counts_.warnings;
  if (warnings_.size() < kMaxWarnings)
    warnings_.push_back(fmt::format("{}:{}: column {}: {} {}", source_, line_, column, word, why));
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
    while (i < line_end && is_blank(base[i])) ++i;
    if (i < line_end && base[i] == '/') {
      // Block delete (ISO 6983-1, 5.4 "/"): the control skips the line when its switch is on.
      // Executing or skipping it changes the path, so the choice is made visibly: skipped.
      if (!ended_) warn(column(i), "'/'", "block delete: the line is skipped, as with the control's switch on");
      continue;
    }
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
      if (c == '#') needs_interpreter(column(i), "'#' parameter");
      if (c == '[') needs_interpreter(column(i), "'[' expression");
      if (c == '@' || c == '^') needs_interpreter(column(i), fmt::format("'{}' polar coordinate", c));
      if (c == '$') needs_interpreter(column(i), "'$' spindle selection");
      // ISO 6983-1 (5.3): ':' and a number mark a program's main start, like an O number.
      if (!is_letter(c) && !(c == ':' && words_.empty()))
        fail(column(i), fmt::format("expected a word (a letter and a number), found {}", shown(c)));
      if (closed_) fail(column(i), "a word after the closing '%' (expected the end of the program)");
      const char letter = c == ':' ? 'O' : upper(c);
      const int col = column(i);
      if (axis_slot(letter) >= 0 && !allowed_[static_cast<std::size_t>(letter - 'A')])
        fail(col, fmt::format("axis word '{}' for an axis this machine does not have (its axes: {})", letter,
                              options_.axes));
      if (letter == 'U' || letter == 'V' || letter == 'W')
        fail(col, fmt::format("axis word '{}': mtcal simulates the axes X Y Z A B C only", letter));
      ++i;
      while (i < line_end && is_blank(base[i])) ++i;
      if (letter == 'O' && i < line_end && base[i] == '<') needs_interpreter(col, "named O-word subroutine");
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
        if (k < line_end && (base[k] == '#' || base[k] == '['))
          needs_interpreter(column(k), fmt::format("'{}' computed by {}", letter,
                                                   base[k] == '#' ? "a '#' parameter" : "a '[' expression"));
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
      if (letter == 'O') {
        // O and a number open a program (ISO 6983-1, 5.3); O and a keyword is RS274NGC's control
        // flow (LinuxCNC's "O Codes": sub, call, if, while, do, repeat ...).
        std::size_t q = k;
        while (q < line_end && is_blank(base[q])) ++q;
        std::size_t r = q;
        while (r < line_end && is_letter(base[r])) ++r;
        std::string key;
        for (std::size_t t = q; t < r; ++t) key += static_cast<char>(std::tolower(static_cast<unsigned char>(base[t])));
        static constexpr const char* kKeywords[] = {"sub",      "endsub",    "call",   "do",       "while",
                                                    "endwhile", "if",        "elseif", "else",     "endif",
                                                    "repeat",   "endrepeat", "break",  "continue", "return"};
        for (const char* kw : kKeywords)
          if (key == kw) needs_interpreter(col, fmt::format("O-word '{}'", kw));
        if (!words_.empty())
          fail(col, "an O program number must open its line (ISO 6983-1: the program's number, alone)");
      }
      words_.push_back({letter, v, col, static_cast<int>(k - line_start) + 1 - col});
      i = k;
    }
    if (!words_.empty()) {
      block_begin_ = line_start;
      block_end_ = line_end;
      ++counts_.blocks;
      if (ended_) {
        // Lines after M2/M30 are never run: said once, with where the program ended.
        if (counts_.blocks > 0 && words_.front().column > 0 && end_line_ > 0) {
          warn(words_.front().column, fmt::format("'{}'", words_.front().letter),
               fmt::format("after the program's end (M2/M30 at line {}): this and later lines are not run", end_line_));
          end_line_ = -end_line_;
        }
        words_.clear();
        continue;
      }
      return true;
    }
  }
  return false;
}

bool GcodeReader::next(GcodeMove& move) {
  for (;;) {
    if (out_next_ < out_.size()) {
      move = out_[out_next_++];
      return true;
    }
    if (!read_block()) return false;
    apply_block();
    out_next_ = 0;
  }
}

bool GcodeReader::next_block(GcodeMove& move, bool& moved) {
  if (!read_block()) return false;
  moved = apply_block();
  out_next_ = out_.size();
  if (moved) move = out_.front();
  return true;
}

void GcodeReader::emit_line(bool rapid, const GcodePosition& end) {
  bool moves = false;
  for (std::size_t s = 0; s < 6; ++s) moves = moves || end[s] != position_[s];
  if (!moves) return;
  GcodeMove m = proto_;
  m.motion = rapid ? GcodeMotion::Rapid : GcodeMotion::Linear;
  m.start = position_;
  m.end = end;
  m.part = static_cast<int>(out_.size());
  out_.push_back(m);
  position_ = end;
  ++counts_.moves;
}

namespace {

// A G code times ten: G59.1 is 591, G0 is 0; -1 for a code with more than one decimal.
int g_code10(double v) {
  const double t = std::round(v * 10);
  return std::abs(t - v * 10) < 1e-9 && t >= 0 && t <= 9999 ? static_cast<int>(t) : -1;
}

std::string g_name(int code10) {
  return code10 % 10 ? fmt::format("G{}.{}", code10 / 10, code10 % 10) : fmt::format("G{}", code10 / 10);
}

bool is_cycle(int motion) { return motion == 73 || (motion >= 81 && motion <= 89); }

// LinuxCNC's retract between pecks of G73 and G83 and its clearance above the last peck's bottom
// when G83 goes back down: 0.010 in, 0.254 mm (LinuxCNC G-code reference, G73 and G83; the
// interpreter's G83_RAPID_DELTA).
constexpr double kPeckDelta = 0.254;
// Bounds on what one block may expand into (memory, not machining: real programs stay far below).
constexpr double kMaxRepeats = 10000;
constexpr double kMaxPecks = 10000;
// The pecks of one block in all (holes of L times pecks per hole): each bound alone let one block
// of G73/G83 with L 10000 expand into 10^8 pecks, gigabytes of moves (found by fuzz_gcode).
constexpr double kMaxBlockPecks = 100000;

}  // namespace

bool GcodeReader::apply_block() {
  out_.clear();
  int motion = -1, motion_col = 0;
  int plane = -1, plane_col = 0, units = -1, units_col = 0, distance = -1, distance_col = 0;
  int arc_distance = -1, length = -1, length_col = 0, system = -1, system_col = 0, retract = -1, retract_col = 0;
  int nonmodal = -1, nonmodal_col = 0;
  std::int64_t n = -1;
  int n_col = 0, f_col = 0, r_col = 0, p_col = 0, q_col = 0, l_col = 0, h_col = 0, s_col = 0, t_col = 0;
  double feed = -1, r = 0, p = 0, q = 0, l = 0, h = 0, spindle = 0, tool = 0;
  std::array<double, 6> axis{};
  std::array<int, 6> axis_col{};  // 0: not in the block
  std::array<double, 3> ijk{};
  std::array<int, 3> ijk_col{};
  int first_axis_col = 0, first_arc_col = 0;
  bool tool_change = false, program_end = false;
  int end_col = 0, blend_col = 0;

  auto once = [&](int& seen_col, const Word& w) {
    if (seen_col) fail(w.column, fmt::format("'{}' given twice in one block (first at column {})", w.letter, seen_col));
    seen_col = w.column;
  };
  auto group = [&](int& value, int& col, int code10, const Word& w, const char* what) {
    if (col)
      fail(w.column,
           fmt::format("two {} codes in one block: {} at column {} and {}", what, g_name(value), col, g_name(code10)));
    value = code10;
    col = w.column;
  };

  for (const Word& w : words_) {
    switch (w.letter) {
      case 'G': {
        const int g = g_code10(w.value);
        if (g < 0) fail(w.column, fmt::format("unsupported G code G{} (expected a code such as G1 or G59.1)", w.value));
        switch (g) {
          case 0:
          case 10:
          case 20:
          case 30:
          case 730:
          case 800:
            if (g == 800) ++counts_.ignored_words;
            group(motion, motion_col, g / 10, w, "motion");
            break;
          case 810:
          case 820:
          case 830:
          case 840:
          case 850:
          case 860:
          case 880:
          case 890: group(motion, motion_col, g / 10, w, "motion"); break;
          case 870:
            fail(w.column,
                 "G87 (back boring) is not expanded: its path depends on the spindle's orientation and "
                 "the tool's offset, which a program does not state (LinuxCNC's interpreter rejects it too)");
          case 40:
          case 100:
          case 280:
          case 281:
          case 300:
          case 301:
          case 530: group(nonmodal, nonmodal_col, g, w, "non-modal"); break;
          case 170:
          case 180:
          case 190: group(plane, plane_col, g / 10, w, "plane"); break;
          case 200:
          case 210: group(units, units_col, g / 10, w, "unit"); break;
          case 900:
          case 910: group(distance, distance_col, g / 10, w, "distance mode"); break;
          case 901: arc_distance = 90; break;
          case 911: arc_distance = 91; break;
          case 430:
          case 490:
            group(length, length_col, g / 10, w, "tool length");
            if (g == 490) ++counts_.ignored_words;
            break;
          case 540:
          case 550:
          case 560:
          case 570:
          case 580:
          case 590: group(system, system_col, g / 10 - 54, w, "coordinate system"); break;
          case 591:
          case 592:
          case 593: group(system, system_col, g - 591 + 6, w, "coordinate system"); break;
          case 980:
          case 990: group(retract, retract_col, g / 10, w, "return mode"); break;
          // Cutter compensation off, feed per minute, spindle in rpm: the states the reader
          // assumes; exact stop and path blending (ISO 6983-1 G61, G64) change how a control
          // follows the programmed path, not the path, which is what is simulated.
          case 400:
          case 940:
          case 970:
          case 610:
          case 611: ++counts_.ignored_words; break;
          case 640:
            ++counts_.ignored_words;
            blend_col = w.column;
            break;
          case 930:
          case 950:
            ++counts_.ignored_words;
            warn(w.column, g_name(g),
                 "(feed per revolution or inverse time): F values are not converted, the moves keep the feed "
                 "in mm/min of the last F read under G94");
            break;
          case 410:
          case 411:
          case 420:
          case 421: needs_interpreter(w.column, fmt::format("{} cutter radius compensation", g_name(g)));
          case 920:
          case 921:
          case 922:
          case 923: needs_interpreter(w.column, fmt::format("{} coordinate system offset", g_name(g)));
          case 431:
          case 432: needs_interpreter(w.column, fmt::format("{} dynamic tool length offset", g_name(g)));
          case 50:
          case 51:
          case 52:
          case 53: needs_interpreter(w.column, fmt::format("{} spline", g_name(g)));
          case 330:
          case 331: needs_interpreter(w.column, fmt::format("{} spindle-synchronised motion", g_name(g)));
          case 70:
          case 80: lathe(w.column, fmt::format("{} (diameter or radius mode)", g_name(g)));
          case 700:
          case 710:
          case 711:
          case 720:
          case 721: lathe(w.column, fmt::format("{} (lathe cycle)", g_name(g)));
          case 760: lathe(w.column, "G76 (threading cycle)");
          case 960: lathe(w.column, "G96 (constant surface speed)");
          case 382:
          case 383:
          case 384:
          case 385:
            fail(w.column, fmt::format("{} probing: the path depends on where the probe trips, which a simulation "
                                       "cannot know",
                                       g_name(g)));
          case 520:
          case 680:
          case 510:
            fail(w.column, fmt::format("unsupported {} (local coordinate system, rotation or scaling): the path "
                                       "would be wrong without it",
                                       g_name(g)));
          default: warn(w.column, g_name(g), "is not known to mtcal's reader and is skipped (it may change the path)");
        }
        break;
      }
      case 'M': {
        ++counts_.m_words;
        ++counts_.ignored_words;
        const double m = w.value;
        if (m == 6) tool_change = true;
        if (m == 2 || m == 30) {
          program_end = true;
          end_col = w.column;
        }
        if (m == 98 || m == 99)
          fail(w.column, fmt::format("M{} subprogram call or return is not read by mtcal's reader (write the "
                                     "subprogram's blocks in line, or use O-word subroutines with LinuxCNC's "
                                     "interpreter)",
                                     m));
        break;
      }
      case 'S':
        once(s_col, w);
        ++counts_.s_words;
        ++counts_.ignored_words;
        spindle = w.value;
        break;
      case 'T':
        once(t_col, w);
        ++counts_.t_words;
        ++counts_.ignored_words;
        if (!(w.value >= 0 && w.value == std::floor(w.value) && w.value < 1e9))
          fail(w.column, fmt::format("expected a whole tool number >= 0 after 'T', found {}", w.value));
        tool = w.value;
        break;
      case 'O': ++counts_.ignored_words; break;  // the program's number
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
        break;
      case 'P':
        once(p_col, w);
        p = w.value;
        break;
      case 'Q':
        once(q_col, w);
        q = w.value;
        break;
      case 'L':
        once(l_col, w);
        l = w.value;
        break;
      case 'H':
        once(h_col, w);
        h = w.value;
        break;
      case 'I':
      case 'J':
      case 'K': {
        const auto s = static_cast<std::size_t>(w.letter - 'I');
        once(ijk_col[s], w);
        ijk[s] = w.value;
        break;
      }
      default: {
        const int slot = axis_slot(w.letter);
        if (slot < 0) {
          warn(w.column, fmt::format("'{}{}'", w.letter, w.value),
               w.letter == 'D' ? "(cutter radius) is for cutter radius compensation, which is not simulated"
                               : "is not a word of mtcal's reader and is skipped");
          break;
        }
        const auto s = static_cast<std::size_t>(slot);
        once(axis_col[s], w);
        axis[s] = w.value;
        if (!first_axis_col) first_axis_col = w.column;
      }
    }
  }

  // In the order RS274NGC executes a block (LinuxCNC G-code reference, "Order of Execution"):
  // feed, spindle, tool, tool change, dwell, plane, units, tool length, coordinate system,
  // distance modes, return mode, the non-modal codes (G10 G28 G30 G53), motion, program end.
  if (units >= 0) inches_ = units == 20;
  const double scale = inches_ ? kMmPerInch : 1.0;
  if (feed >= 0) feed_ = feed * scale;
  if (s_col) spindle_ = spindle;
  if (t_col) selected_tool_ = static_cast<int>(tool);
  if (tool_change) {
    tool_ = selected_tool_;
    ++counts_.tool_changes;
  }
  if (nonmodal == 40) {
    if (!p_col) fail(nonmodal_col, "G4 (dwell) without P (expected the dwell in seconds)");
    p_col = 0;  // used
  }
  if (blend_col && (p_col || q_col)) {
    warn(p_col ? p_col : q_col, p_col ? fmt::format("'G64 P{}'", p) : fmt::format("'G64 Q{}'", q),
         "(path blending tolerance) is not simulated: the programmed path is evaluated");
    p_col = q_col = 0;
  }
  if (plane >= 0) plane_ = plane == 17 ? GcodePlane::XY : plane == 18 ? GcodePlane::ZX : GcodePlane::YZ;
  const GcodeSetup& setup = options_.setup;
  if (length == 43) {
    // G43 H<n>: tool n's offsets from the tool table; without H, the tool in the spindle's.
    int number = tool_;
    if (h_col) {
      if (!(h >= 0 && h == std::floor(h) && h < 1e9))
        fail(h_col, fmt::format("expected a whole tool number >= 0 after 'H', found {}", h));
      number = static_cast<int>(h);
      h_col = 0;
    }
    if (number <= 0) length_.fill(0);
    if (number > 0) {
      const auto it = setup.tools.find(number);
      if (it == setup.tools.end())
        fail(length_col, setup.has_tool_table
                             ? fmt::format("G43 asks for the length of tool {}, which the tool table has not", number)
                             : fmt::format("G43 asks for the length of tool {} (expected a tool table)", number));
      length_ = it->second.offset;
    }
  } else if (length == 49) {
    length_.fill(0);
  }
  if (system >= 0) {
    work_system_ = system;
    work_ = setup.work_offsets[static_cast<std::size_t>(system)];
  }
  if (distance >= 0) incremental_ = distance == 91;
  if (arc_distance >= 0) arc_absolute_ = arc_distance == 90;
  if (retract >= 0) retract_initial_ = retract == 98;

  proto_ = GcodeMove{};
  proto_.plane = plane_;
  proto_.line = line_;
  proto_.n = n;
  proto_.feed = feed_;
  proto_.tool = tool_;
  proto_.spindle = spindle_;

  auto program_value = [&](std::size_t s) { return s < 3 ? axis[s] * scale : axis[s]; };
  // Where the block's axis words send the axes from `from`: G90 positions in the work
  // coordinates (plus the offsets in effect), G91 steps.
  auto target = [&](const GcodePosition& from) {
    GcodePosition end = from;
    for (std::size_t s = 0; s < 6; ++s) {
      if (!axis_col[s]) continue;
      end[s] = incremental_ ? from[s] + program_value(s) : program_value(s) + offset(s);
      if (!std::isfinite(end[s])) fail(axis_col[s], fmt::format("the position of {} is not finite", kGcodeAxes[s]));
    }
    return end;
  };
  const bool has_ijk = ijk_col[0] || ijk_col[1] || ijk_col[2];
  if (has_ijk)
    first_arc_col = *std::min_element(ijk_col.begin(), ijk_col.end(),
                                      [](int a, int b) { return (a ? a : 1 << 30) < (b ? b : 1 << 30); });
  bool axes_used = false;

  switch (nonmodal) {
    case 100: {
      // G10 L2 P<n>: set work coordinate system n's offset (LinuxCNC G-code reference, G10 L2;
      // Fanuc's programmable data input); P0 is the system in effect.
      if (!l_col) fail(nonmodal_col, "G10 without L (expected L2: a work offset)");
      if (l != 2) needs_interpreter(l_col, fmt::format("G10 L{}", l));
      if (!p_col) fail(nonmodal_col, "G10 L2 without P (expected the coordinate system: 1 for G54 .. 9 for G59.3)");
      if (!(p >= 0 && p <= 9 && p == std::floor(p)))
        fail(p_col,
             fmt::format("expected P0 to P9 after G10 L2 (0: the system in effect, 1: G54 .. 9: G59.3), found P{}", p));
      if (r_col) needs_interpreter(r_col, "G10 L2 R (a rotated coordinate system)");
      const auto index = static_cast<std::size_t>(p == 0 ? work_system_ : static_cast<int>(p) - 1);
      for (std::size_t s = 0; s < 6; ++s)
        if (axis_col[s]) options_.setup.work_offsets[index][s] = program_value(s);
      if (static_cast<int>(index) == work_system_) work_ = options_.setup.work_offsets[index];
      l_col = p_col = 0;
      axes_used = true;
      break;
    }
    case 280:
    case 300: {
      // G28/G30: to the stored position by way of the point the axis words give, the named axes
      // only; all axes when none is named (LinuxCNC G-code reference, G28 G30).
      const GcodePosition& stored = nonmodal == 280 ? options_.setup.g28 : options_.setup.g30;
      proto_.motion = GcodeMotion::Rapid;
      if (first_axis_col) emit_line(true, target(position_));
      GcodePosition end = position_;
      for (std::size_t s = 0; s < 6; ++s)
        if ((!first_axis_col || axis_col[s]) && allowed_[static_cast<std::size_t>(kGcodeAxes[s] - 'A')])
          end[s] = stored[s];
      emit_line(true, end);
      ++counts_.expanded_blocks;
      axes_used = true;
      break;
    }
    case 281:
    case 301:
      if (first_axis_col)
        fail(first_axis_col, fmt::format("axis words with {} (it stores the present position)", g_name(nonmodal)));
      (nonmodal == 281 ? options_.setup.g28 : options_.setup.g30) = position_;
      break;
    case 530: {
      // G53: this block's move in machine coordinates (the frame of the moves), no offsets.
      const int m = motion >= 0 ? motion : motion_;
      if (m != 0 && m != 1)
        fail(nonmodal_col, fmt::format("G53 with {} (expected G0 or G1)",
                                       m < 0 ? std::string("no motion mode") : fmt::format("G{}", m)));
      if (incremental_) fail(nonmodal_col, "G53 under G91 (expected absolute positions, G90)");
      GcodePosition end = position_;
      for (std::size_t s = 0; s < 6; ++s)
        if (axis_col[s]) end[s] = program_value(s);
      if (motion >= 0) motion_ = motion;
      emit_line(m == 0, end);
      if (!out_.empty()) ++counts_.expanded_blocks;
      axes_used = true;
      break;
    }
    default: break;
  }

  if (motion >= 0) {
    if (!is_cycle(motion) || motion != motion_) in_cycle_series_ = in_cycle_series_ && is_cycle(motion);
    motion_ = motion;
  }
  if (!is_cycle(motion_)) in_cycle_series_ = false;

  if (!axes_used && is_cycle(motion_)) {
    // Canned cycles (ISO 6983-1 G81-G89; the motions as LinuxCNC's G-code reference states them
    // for G73 and G81-G89, which its interpreter rs274 prints): over the hole at the present
    // level, rapid to R, the cycle, then back to the clearance: G98 the level before the series
    // of cycles began (R if that was lower), G99 R. G91: X Y (the plane's axes) are steps repeated
    // L times, R is a step from the present level, the depth a step from R.
    const PlaneAxes pa = plane_axes(plane_);
    const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v),
               w = static_cast<std::size_t>(pa.w);
    const std::string name = fmt::format("G{}", motion_);
    for (std::size_t s = 3; s < 6; ++s)
      if (axis_col[s])
        fail(axis_col[s], fmt::format("rotary axis word '{}' in a canned cycle ({})", kGcodeAxes[s], name));
    if (has_ijk) fail(first_arc_col, fmt::format("I, J, K in a canned cycle ({}: expected X Y Z R Q P L)", name));
    if (!in_cycle_series_) {
      in_cycle_series_ = true;
      cycle_initial_ = position_[w];
      cycle_r_set_ = cycle_depth_set_ = false;
      cycle_q_ = cycle_p_ = 0;
    }
    if (r_col) {
      cycle_r_ = r * scale;
      cycle_r_set_ = true;
      r_col = 0;
    }
    if (axis_col[w]) {
      cycle_depth_ = program_value(w);
      cycle_depth_set_ = true;
    }
    if (q_col) {
      cycle_q_ = q * scale;
      if (motion_ == 73 || motion_ == 83) q_col = 0;
    }
    if (p_col) {
      cycle_p_ = p;
      if (motion_ == 82 || motion_ == 86 || motion_ == 88 || motion_ == 89) p_col = 0;
    }
    int repeats = 1;
    const int repeats_col = l_col;
    if (l_col) {
      // A bound so that one block cannot expand into unbounded memory.
      if (!(l >= 0 && l == std::floor(l) && l <= kMaxRepeats))
        fail(l_col, fmt::format("expected a whole number of repeats from 0 to {} after 'L', found {}", kMaxRepeats, l));
      repeats = static_cast<int>(l);
      l_col = 0;
    }
    if (first_axis_col) {
      const int at = motion_col ? motion_col : first_axis_col;
      if (!cycle_r_set_)
        fail(at, fmt::format("{} without R (expected the retract level R in this block or an earlier one of the "
                             "cycle)",
                             name));
      if (!cycle_depth_set_)
        fail(at, fmt::format("{} without {} (expected the hole's depth in this block or an earlier one of the cycle)",
                             name, kGcodeAxes[w]));
      if ((motion_ == 73 || motion_ == 83) && !(cycle_q_ > 0))
        fail(at, fmt::format("{} without a peck Q > 0 (expected Q, the depth of each peck)", name));
      const double level0 = position_[w];
      const double r_level = incremental_ ? level0 + cycle_r_ : cycle_r_ + offset(w);
      const double bottom = incremental_ ? r_level + cycle_depth_ : cycle_depth_ + offset(w);
      if ((motion_ == 73 || motion_ == 83) && (r_level - bottom) / cycle_q_ > kMaxPecks)
        fail(at, fmt::format("{}: Q {} mm gives more than {} pecks to the depth (expected a larger Q)", name,
                             fmt_mm(cycle_q_), kMaxPecks));
      if ((motion_ == 73 || motion_ == 83) && repeats * std::ceil((r_level - bottom) / cycle_q_) > kMaxBlockPecks)
        fail(repeats_col ? repeats_col : at,
             fmt::format("{}: L {} holes of {} pecks each give more than {} pecks in one block (expected a smaller L "
                         "or a larger Q)",
                         name, repeats, std::ceil((r_level - bottom) / cycle_q_), kMaxBlockPecks));
      if (bottom > r_level)
        fail(at, fmt::format("{}: the hole's bottom {} = {} mm lies above R = {} mm (expected R at or above it)", name,
                             kGcodeAxes[w], fmt_mm(bottom), fmt_mm(r_level)));
      if (motion_ == 88 && repeats > 0)
        warn(at, name,
             "stops at the hole's bottom for the operator to retract by hand; the simulated path "
             "goes on from there, as LinuxCNC's interpreter does");
      const double clear = retract_initial_ ? std::max(cycle_initial_, r_level) : r_level;
      auto to = [&](double level) {
        GcodePosition e = position_;
        e[w] = level;
        return e;
      };
      if (position_[w] < r_level) emit_line(true, to(r_level));
      for (int k = 0; k < repeats; ++k) {
        GcodePosition hole = position_;
        for (std::size_t s : {u, v})
          if (axis_col[s]) hole[s] = incremental_ ? position_[s] + program_value(s) : program_value(s) + offset(s);
        emit_line(true, hole);
        emit_line(true, to(r_level));
        switch (motion_) {
          case 73:
          case 83: {
            double depth = r_level;
            while (depth > bottom) {
              depth = std::max(depth - cycle_q_, bottom);
              emit_line(false, to(depth));
              if (depth > bottom) {
                if (motion_ == 83) emit_line(true, to(r_level));
                emit_line(true, to(depth + kPeckDelta));
              }
            }
            emit_line(true, to(clear));
            break;
          }
          case 81:
          case 82:
          case 86:
            emit_line(false, to(bottom));
            emit_line(true, to(clear));
            break;
          case 84:
          case 89:
            emit_line(false, to(bottom));
            emit_line(false, to(clear));
            break;
          case 85:
            emit_line(false, to(bottom));
            emit_line(false, to(r_level));
            emit_line(true, to(clear));
            break;
          case 88: emit_line(false, to(bottom)); break;
          default: break;
        }
        ++counts_.cycles;
      }
      ++counts_.expanded_blocks;
    }
    axes_used = true;
  }

  if (!axes_used) {
    if ((has_ijk || r_col) && motion_ != 2 && motion_ != 3)
      fail(has_ijk ? first_arc_col : r_col,
           fmt::format("I, J, K and R go with G2 or G3, found them with {}",
                       motion_ < 0 ? std::string("no motion mode") : fmt::format("G{}", motion_)));
    if (has_ijk && r_col)
      fail(std::max(r_col, first_arc_col), "R and I/J/K in one block (expected the arc's centre one way: I J K or R)");
    if (first_axis_col && (motion_ < 0 || motion_ == 80))
      fail(first_axis_col, motion_ == 80 ? "axis word under G80 (no motion mode: expected G0, G1, G2 or G3 first)"
                                         : "axis word with no motion mode in effect (expected G0, G1, G2 or G3 in "
                                           "this or an earlier block)");
    const bool arc = motion_ == 2 || motion_ == 3;
    if (arc && p_col) needs_interpreter(p_col, "P (turns of a helix) with G2/G3");
    if (first_axis_col || (arc && (has_ijk || r_col))) {
      const GcodePosition end = target(position_);
      GcodeMove move = proto_;
      move.motion = static_cast<GcodeMotion>(motion_);
      move.start = position_;
      move.end = end;
      if (arc) {
        if (!first_arc_col) first_arc_col = r_col;
        const PlaneAxes pa = plane_axes(plane_);
        const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v),
                   w = static_cast<std::size_t>(pa.w);
        const int at = motion_col ? motion_col : (first_axis_col ? first_axis_col : first_arc_col);
        if (!has_ijk && !r_col)
          fail(at, fmt::format("arc (G{}) with no centre (expected I J K offsets or R)", motion_));
        const double su = position_[u], sv = position_[v], eu = end[u], ev = end[v];
        const double chord = std::hypot(eu - su, ev - sv);
        const bool ccw = motion_ == 3;
        double cu = 0, cv = 0;
        if (has_ijk) {
          // RS274NGC: I J K are offsets of the centre from the start along X Y Z (G91.1, the
          // default), or the centre's position (G90.1), whatever G90/G91.
          if (ijk_col[w])
            fail(ijk_col[w], fmt::format("'{}' is no centre offset in the {} plane (expected {} and {})",
                                         static_cast<char>('I' + w), to_string(plane_), static_cast<char>('I' + u),
                                         static_cast<char>('I' + v)));
          if (!ijk_col[u] && !ijk_col[v])
            fail(at, fmt::format("arc (G{}) with no centre in the {} plane (expected {} or {})", motion_,
                                 to_string(plane_), static_cast<char>('I' + u), static_cast<char>('I' + v)));
          cu = arc_absolute_ ? ijk[u] * scale + offset(u) : su + ijk[u] * scale;
          cv = arc_absolute_ ? ijk[v] * scale + offset(v) : sv + ijk[v] * scale;
          const double r0 = std::hypot(su - cu, sv - cv), r1 = std::hypot(eu - cu, ev - cv);
          if (!(r0 > kSamePoint)) fail(first_arc_col, "the arc's centre is its start point (expected a radius > 0)");
          const double tol = std::max(kArcRadiusTolerance, kArcRadiusRelative * std::max(r0, r1));
          if (!(std::abs(r0 - r1) <= tol))
            fail(first_arc_col, fmt::format("the arc's start radius {} mm and end radius {} mm differ by {} mm "
                                            "(expected the end on the circle, within {} mm)",
                                            fmt_mm(r0), fmt_mm(r1), fmt_mm(std::abs(r0 - r1)), fmt_mm(tol)));
          double sweep = 0;
          if (chord <= kSamePoint) {
            sweep = ccw ? kTwoPi : -kTwoPi;
          } else {
            const double a = std::atan2((su - cu) * (ev - cv) - (sv - cv) * (eu - cu),
                                        (su - cu) * (eu - cu) + (sv - cv) * (ev - cv));
            sweep = ccw ? (a <= 0 ? a + kTwoPi : a) : (a >= 0 ? a - kTwoPi : a);
          }
          move.sweep = sweep;
        } else {
          // R form: the centre lies on the chord's perpendicular bisector; R > 0 takes the arc of
          // at most 180 deg, R < 0 the longer one (RS274NGC 3.5.3.1).
          const double rr = std::abs(r * scale);
          if (chord <= kSamePoint)
            fail(r_col, "an R arc whose end is its start (expected I J K for a full circle, or another end point)");
          const double half = chord / 2;
          const double tol = std::max(kArcRadiusTolerance, kArcRadiusRelative * rr);
          if (rr < half - tol)
            fail(r_col, fmt::format("R {} mm is shorter than half the chord, {} mm (expected |R| >= {} mm)", fmt_mm(rr),
                                    fmt_mm(half), fmt_mm(half)));
          const double hh = std::sqrt(std::max(0.0, rr * rr - half * half));
          const double nu = -(ev - sv) / chord, nv = (eu - su) / chord;  // left of the chord
          // The centre is on the left of travel for a G3 arc under 180 deg.
          const double side = (ccw ? 1.0 : -1.0) * (r < 0 ? -1.0 : 1.0);
          cu = (su + eu) / 2 + side * hh * nu;
          cv = (sv + ev) / 2 + side * hh * nv;
          const double small = 2 * std::asin(std::min(1.0, half / std::max(rr, half)));
          const double sweep = r < 0 ? kTwoPi - small : small;
          move.sweep = ccw ? sweep : -sweep;
        }
        r_col = 0;
        move.centre[u] = cu;
        move.centre[v] = cv;
        move.centre[w] = position_[w];
      }
      move.part = 0;
      out_.push_back(move);
      position_ = end;
      ++counts_.moves;
    }
  }

  for (const Word& w : words_)
    if ((w.letter == 'P' && p_col == w.column) || (w.letter == 'Q' && q_col == w.column) ||
        (w.letter == 'L' && l_col == w.column) || (w.letter == 'H' && h_col == w.column) ||
        (w.letter == 'R' && r_col == w.column))
      warn(w.column, fmt::format("'{}{}'", w.letter, w.value), "has no meaning in this block and is skipped");
  if (!out_.empty()) {
    bool shifted = false;
    for (std::size_t s = 0; s < 6; ++s) shifted = shifted || offset(s) != 0;
    if (shifted) ++counts_.offset_blocks;
  }
  if (program_end) {
    ended_ = true;
    end_line_ = line_;
    (void)end_col;
  }
  return !out_.empty();
}

GcodeProgram parse_gcode(std::string_view text, const std::string& source, const GcodeOptions& options) {
  GcodeReader reader(text, source, options);
  GcodeProgram p;
  p.source = source;
  GcodeMove m;
  while (reader.next(m)) p.moves.push_back(m);
  p.counts = reader.counts();
  p.warnings = reader.warnings();
  return p;
}

GcodeProgram read_gcode(const std::string& path, const GcodeOptions& options) {
  const std::string text = read_text_file(path, "G-code program");
  return parse_gcode(text, path, options);
}

}  // namespace mtcal

namespace mtcal {

std::string_view work_system_name(int index) {
  static constexpr std::string_view kNames[9] = {"G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"};
  return index >= 0 && index < 9 ? kNames[index] : std::string_view("?");
}

std::optional<GcodeNeedsInterpreter> gcode_needs_interpreter(std::string_view text, const std::string& source,
                                                             const GcodeOptions& options) {
  try {
    GcodeReader reader(text, source, options);
    GcodeMove m;
    while (reader.next(m)) {
    }
  } catch (const GcodeNeedsInterpreter& e) {
    return e;
  }
  return std::nullopt;
}

void refuse_lathe_program(std::string_view text, const std::string& source) {
  int line = 1;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '(') {
      while (i < text.size() && text[i] != ')' && text[i] != '\n') ++i;
    } else if (c == ';') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if ((c == 'G' || c == 'g') && (i == 0 || !is_letter(text[i - 1]))) {
      const std::size_t col_at = i;
      std::size_t k = i + 1;
      while (k < text.size() && is_blank(text[k])) ++k;
      std::size_t e = k;
      while (e < text.size() && (is_digit(text[e]) || text[e] == '.')) ++e;
      double v = -1;
      if (e > k) {
        const auto [p, ec] = std::from_chars(text.data() + k, text.data() + e, v, std::chars_format::fixed);
        if (ec != std::errc() || p != text.data() + e) v = -1;
      }
      const char* what = v == 7 || v == 8                ? "diameter or radius mode"
                         : v == 70 || v == 71 || v == 72 ? "lathe cycle"
                         : v == 76                       ? "threading cycle"
                         : v == 96                       ? "constant surface speed"
                                                         : nullptr;
      if (what) {
        std::size_t bol = col_at;
        while (bol > 0 && text[bol - 1] != '\n') --bol;
        throw GcodeLatheProgram({source, line, ""},
                                fmt::format("column {}: G{} ({}): a lathe program (mtcal simulates milling machines)",
                                            col_at - bol + 1, v, what));
      }
      i = std::max(e, i + 1);
    } else {
      ++i;
    }
  }
}

namespace {

// A number of a setup file's line: the whole token must be one.
bool parse_number(std::string_view token, double& v) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  return ec == std::errc() && end == token.data() + token.size() && std::isfinite(v);
}

}  // namespace

std::map<int, GcodeTool> parse_tool_table(std::string_view text, const std::string& source, double scale) {
  std::map<int, GcodeTool> tools;
  int line = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto nl = text.find('\n', pos);
    std::string_view row = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    ++line;
    if (const auto semi = row.find(';'); semi != std::string_view::npos) row = row.substr(0, semi);
    int number = -1;
    GcodeTool tool;
    tool.line = line;
    std::size_t i = 0;
    bool any = false;
    while (i < row.size()) {
      if (is_blank(row[i])) {
        ++i;
        continue;
      }
      const char letter = upper(row[i]);
      std::size_t k = i + 1;
      while (k < row.size() && !is_blank(row[k])) ++k;
      const std::string_view token = row.substr(i + 1, k - i - 1);
      const int col = static_cast<int>(i) + 1;
      double v = 0;
      if (!std::strchr("TPXYZABCUVWDIJQ", letter) || !is_letter(row[i]))
        throw InputError(
            {source, line, ""},
            fmt::format("column {}: expected a tool table word (T P X Y Z A B C U V W D I J Q), found '{}'", col,
                        printable(row.substr(i, k - i), 20)));
      if (!parse_number(token, v))
        throw InputError({source, line, ""}, fmt::format("column {}: expected a number after '{}', found '{}'", col,
                                                         letter, printable(token, 20)));
      any = true;
      const int slot = axis_slot(letter);
      if (letter == 'T') {
        if (!(v >= 0 && v == std::floor(v) && v < 1e9))
          throw InputError({source, line, ""}, fmt::format("column {}: expected a whole tool number >= 0, found T{}",
                                                           col, printable(token, 20)));
        number = static_cast<int>(v);
      } else if (slot >= 0) {
        tool.offset[static_cast<std::size_t>(slot)] = slot < 3 ? v * scale : v;
      } else if (letter == 'D') {
        tool.diameter = v * scale;
      }
      // P (pocket), U V W, I J Q (lathe tool angles and orientation): not simulated.
      i = k;
    }
    if (!any) continue;
    if (number < 0) throw InputError({source, line, ""}, "expected the tool's number (a T word) on its line");
    if (const auto it = tools.find(number); it != tools.end())
      throw InputError({source, line, ""},
                       fmt::format("tool {} listed twice (first at line {})", number, it->second.line));
    tools.emplace(number, tool);
  }
  return tools;
}

std::map<int, GcodeTool> read_tool_table(const std::string& path, double scale) {
  return parse_tool_table(read_text_file(path, "tool table"), path, scale);
}

void parse_parameter_file(std::string_view text, const std::string& source, GcodeSetup& setup, double scale) {
  int line = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto nl = text.find('\n', pos);
    std::string_view row = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    ++line;
    std::vector<std::string_view> tokens;
    std::size_t i = 0;
    while (i < row.size()) {
      if (is_blank(row[i])) {
        ++i;
        continue;
      }
      std::size_t k = i;
      while (k < row.size() && !is_blank(row[k])) ++k;
      tokens.push_back(row.substr(i, k - i));
      i = k;
    }
    if (tokens.empty()) continue;
    double number = 0, value = 0;
    if (tokens.size() != 2 || !parse_number(tokens[0], number) || !parse_number(tokens[1], value) ||
        number != std::floor(number) || number < 1 || number > 99999)
      throw InputError({source, line, ""},
                       fmt::format("expected a parameter's number and value (\"5221 10.0\"), found '{}'",
                                   printable(row)));
    const int n = static_cast<int>(number);
    auto set_axis = [&](GcodePosition& p, int first) {
      const auto s = static_cast<std::size_t>(n - first);
      p[s] = s < 3 ? value * scale : value;
    };
    if (n >= 5161 && n <= 5166)
      set_axis(setup.g28, 5161);
    else if (n >= 5181 && n <= 5186)
      set_axis(setup.g30, 5181);
    else if (n == 5220) {
      if (!(value >= 1 && value <= 9 && value == std::floor(value)))
        throw InputError({source, line, ""},
                         fmt::format("parameter 5220 (the coordinate system) must be 1 (G54) to 9 (G59.3), found {}",
                                     value));
      setup.work_system = static_cast<int>(value) - 1;
    } else if (n >= 5221 && n <= 5389 && (n - 5221) % 20 < 6) {
      set_axis(setup.work_offsets[static_cast<std::size_t>((n - 5221) / 20)], 5221 + (n - 5221) / 20 * 20);
    }
  }
}

void read_parameter_file(const std::string& path, GcodeSetup& setup, double scale) {
  parse_parameter_file(read_text_file(path, "parameter file"), path, setup, scale);
}

}  // namespace mtcal
