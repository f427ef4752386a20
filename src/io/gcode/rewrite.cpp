#include "mtcal/io/gcode/rewrite.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {


int axis_slot(char letter) {
  const char* p = std::find(std::begin(kGcodeAxes), std::end(kGcodeAxes), letter);
  return p == std::end(kGcodeAxes) ? -1 : static_cast<int>(p - std::begin(kGcodeAxes));
}

bool is_motion_word(const GcodeReader::Word& w) {
  return w.letter == 'G' && (w.value == 0 || w.value == 1 || w.value == 2 || w.value == 3);
}

int motion_code(GcodeMotion m) { return static_cast<int>(m); }

// A value with `decimals` digits, trailing zeros dropped but one digit after the point kept.
std::string number_text(double v, int decimals) {
  std::string s = fmt::format("{:.{}f}", v, decimals);
  const auto dot = s.find('.');
  if (dot != std::string::npos) {
    std::size_t end = s.size();
    while (end > dot + 2 && s[end - 1] == '0') --end;
    s.resize(end);
  }
  if (s == "-0.0") s = "0.0";
  return s;
}

double parse_text(const std::string& s) {
  double v = 0;
  std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::fixed);
  return v;
}

struct Edit {
  std::size_t begin, end;  // byte range of the line replaced
  std::string text;
};

class Rewriter {
 public:
  Rewriter(std::string_view text, const std::string& source, const GcodeOptions& options,
           std::span<const CorrectedMove> moves, const GcodeRewriteOptions& ro)
      : text_(text), source_(source), options_(options), moves_(moves), ro_(ro), held_(options.start) {
    for (char c : options.axes) {
      const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      if (axis_slot(u) >= 0) has_[static_cast<std::size_t>(axis_slot(u))] = true;
    }
    if (ro.decimals < 0 || ro.decimals > 12)
      throw InputError({"decimals", 0, ""},
                       fmt::format("expected 0 to 12 digits after the decimal point, found {}", ro.decimals));
    // Lines as the reader counts them: split at '\n'.
    std::size_t pos = 0;
    while (pos < text.size()) {
      const auto nl = text.find('\n', pos);
      const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
      lines_.push_back(text.substr(pos, end - pos));
      pos = nl == std::string_view::npos ? text.size() : nl + 1;
    }
    ends_with_newline_ = !text.empty() && text.back() == '\n';
  }

  std::string run(GcodeRewriteSummary& sum) {
    GcodeReader reader(text_, source_, options_);
    GcodeMove mv;
    bool moved = false;
    std::size_t next_line = 1, index = 0;
    while (reader.next_block(mv, moved)) {
      const auto line = static_cast<std::size_t>(reader.block_line());
      while (next_line < line) copy(next_line++);
      if (!moved) {
        for (const auto& w : reader.block_words())
          if (is_motion_word(w)) out_motion_ = static_cast<int>(w.value);
        copy(next_line++);
        continue;
      }
      if (index >= moves_.size() || moves_[index].line != static_cast<int>(line))
        throw Error(
            fmt::format("{}:{}: the corrected moves do not belong to this program (expected a corrected "
                        "move for this line, found {})",
                        source_, line,
                        index < moves_.size() ? fmt::format("one for line {}", moves_[index].line)
                                              : std::string("none left")));
      rewrite(reader, moves_[index++], sum);
      ++next_line;
    }
    if (index != moves_.size())
      throw Error(fmt::format("{}: {} corrected moves but the program has {} moves", source_, moves_.size(), index));
    while (next_line <= lines_.size()) copy(next_line++);
    if (!ends_with_newline_ && !out_.empty() && out_.back() == '\n') out_.pop_back();
    sum.lines_in = lines_.size();
    return std::move(out_);
  }

 private:
  void copy(std::size_t line) {
    out_ += lines_[line - 1];
    out_ += '\n';
  }

  double scale(std::size_t slot) const { return slot < 3 && inches_ ? kMmPerInch : 1.0; }
  double half_unit() const { return 0.5 * std::pow(10.0, -decimals_); }

  // The text of axis `slot`'s word for the value `v` (program units, mm/deg) and the value the
  // controller will take from it.
  std::pair<std::string, double> axis_text(std::size_t slot, double v) const {
    const double sc = scale(slot);
    const double line_value = incremental_ ? (v - held_[slot]) / sc : v / sc;
    const std::string t = number_text(line_value, decimals_);
    const double parsed = parse_text(t) * sc;
    return {t, incremental_ ? held_[slot] + parsed : parsed};
  }

  // What a written word of axis `slot` with line value `value` means, as the reader computes it.
  double meant(std::size_t slot, double value) const {
    const double v = value * scale(slot);
    return incremental_ ? held_[slot] + v : v;
  }

  // Arc words of a piece from the held (written) start: offsets or radius, line units.
  struct ArcWords {
    std::array<double, 3> offset{};
    double radius = 0;
  };
  ArcWords arc_words(const CorrectedPiece& p, GcodePlane plane) const {
    const PlaneAxes pa = plane_axes(plane);
    ArcWords a;
    const double sc = inches_ ? kMmPerInch : 1.0;
    for (int s : {pa.u, pa.v}) {
      const auto k = static_cast<std::size_t>(s);
      a.offset[k] = (p.centre[k] - held_[k]) / sc;
    }
    const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v);
    const double r = std::hypot(p.centre[u] - held_[u], p.centre[v] - held_[v]) / sc;
    a.radius = std::abs(p.sweep) > std::numbers::pi ? -r : r;
    return a;
  }

  void rewrite(const GcodeReader& reader, const CorrectedMove& cm, GcodeRewriteSummary& sum) {
    inches_ = reader.inches();
    incremental_ = reader.incremental();
    decimals_ = ro_.decimals + (inches_ ? 1 : 0);
    const GcodePlane plane = reader.plane();
    const std::string_view line = reader.block_text();
    const bool cr = !line.empty() && line.back() == '\r';
    const auto& words = reader.block_words();
    const CorrectedPiece& first = cm.pieces.front();
    const bool arc = first.motion == GcodeMotion::ArcCW || first.motion == GcodeMotion::ArcCCW;
    const int code = motion_code(first.motion);
    auto at = [](int column) { return static_cast<std::size_t>(column - 1); };

    std::vector<Edit> edits;
    // Arc words first: they are relative to the start, the position held before this line.
    const ArcWords aw = arc ? arc_words(first, plane) : ArcWords{};
    const PlaneAxes pa = plane_axes(plane);
    std::array<bool, 3> offset_written{};
    bool has_r = false;
    for (const auto& w : words) {
      const bool offset = w.letter == 'I' || w.letter == 'J' || w.letter == 'K';
      if (!offset && w.letter != 'R') continue;
      if (!arc) {
        // A straight piece: the arc words go, with the blanks before them.
        std::size_t b = at(w.column);
        while (b > 0 && (line[b - 1] == ' ' || line[b - 1] == '\t')) --b;
        edits.push_back({b, at(w.column) + static_cast<std::size_t>(w.length), ""});
        continue;
      }
      double want = 0;
      if (offset) {
        const auto k = static_cast<std::size_t>(w.letter - 'I');
        want = aw.offset[k];
        offset_written[k] = true;
      } else {
        want = aw.radius;
        has_r = true;
      }
      if (std::abs(want - w.value) > half_unit())
        edits.push_back({at(w.column), at(w.column) + static_cast<std::size_t>(w.length),
                         std::string(1, w.letter) + number_text(want, decimals_)});
    }
    std::string added_arc;
    if (arc && !has_r)
      for (int s : {pa.u, pa.v}) {
        const auto k = static_cast<std::size_t>(s);
        if (!offset_written[k] && std::abs(aw.offset[k]) > half_unit())
          added_arc += fmt::format(" {}{}", static_cast<char>('I' + k), number_text(aw.offset[k], decimals_));
      }

    // Axis words: new values where they differ from what the word means.
    std::array<bool, 6> in_line{};
    std::size_t anchor = 0, first_target = std::string_view::npos;
    int motion_word = -1;
    for (std::size_t i = 0; i < words.size(); ++i) {
      const auto& w = words[i];
      const std::size_t end = at(w.column) + static_cast<std::size_t>(w.length);
      if (is_motion_word(w)) {
        motion_word = static_cast<int>(i);
        anchor = std::max(anchor, end);
      }
      const bool target_word = axis_slot(w.letter) >= 0 || std::strchr("IJKR", w.letter) != nullptr;
      if (target_word) {
        first_target = std::min(first_target, at(w.column));
        anchor = std::max(anchor, end);
      }
      const int slot = axis_slot(w.letter);
      if (slot < 0) continue;
      const auto s = static_cast<std::size_t>(slot);
      in_line[s] = true;
      const double v = first.end[s];
      const double m = meant(s, w.value);
      if (std::abs(m - v) <= half_unit() * scale(s)) {
        next_held_[s] = m;
        continue;
      }
      auto [t, written] = axis_text(s, v);
      next_held_[s] = written;
      edits.push_back({at(w.column), end, std::string(1, w.letter) + t});
    }
    if (anchor == 0 && !words.empty()) {
      const auto& w = words.back();
      anchor = at(w.column) + static_cast<std::size_t>(w.length);
    }
    std::string added_axes;
    for (std::size_t s = 0; s < 6; ++s) {
      if (in_line[s]) continue;
      next_held_[s] = held_[s];
      if (!has_[s] || std::abs(first.end[s] - held_[s]) <= half_unit() * scale(s)) continue;
      auto [t, written] = axis_text(s, first.end[s]);
      next_held_[s] = written;
      added_axes += fmt::format(" {}{}", kGcodeAxes[s], t);
    }
    if (!added_axes.empty() || !added_arc.empty()) edits.push_back({anchor, anchor, added_axes + added_arc});
    // The motion word.
    if (motion_word >= 0) {
      const auto& w = words[static_cast<std::size_t>(motion_word)];
      if (static_cast<int>(w.value) != code)
        edits.push_back({at(w.column), at(w.column) + static_cast<std::size_t>(w.length), fmt::format("G{}", code)});
    } else if (out_motion_ != code) {
      const std::size_t where = first_target == std::string_view::npos ? anchor : first_target;
      edits.push_back({where, where, fmt::format("G{} ", code)});
    }
    out_motion_ = code;

    std::string text(line);
    std::stable_sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    for (const auto& e : edits) text.replace(e.begin, e.end - e.begin, e.text);
    if (!edits.empty()) ++sum.lines_changed;
    out_ += text;
    out_ += '\n';
    held_ = next_held_;

    for (std::size_t i = 1; i < cm.pieces.size(); ++i) {
      const std::string l = piece_line(cm.pieces[i], plane);
      if (l.empty()) continue;
      out_ += l;
      if (cr) out_ += '\r';
      out_ += '\n';
      ++sum.lines_added;
    }
  }

  // A further piece as a line of its own: the motion word, the axes that change, the arc's offsets.
  std::string piece_line(const CorrectedPiece& p, GcodePlane plane) {
    const bool arc = p.motion == GcodeMotion::ArcCW || p.motion == GcodeMotion::ArcCCW;
    const ArcWords aw = arc ? arc_words(p, plane) : ArcWords{};
    std::string axes;
    for (std::size_t s = 0; s < 6; ++s) {
      if (!has_[s] || std::abs(p.end[s] - held_[s]) <= half_unit() * scale(s)) continue;
      auto [t, written] = axis_text(s, p.end[s]);
      held_[s] = written;
      axes += fmt::format(" {}{}", kGcodeAxes[s], t);
    }
    if (axes.empty() && !arc) return {};
    std::string l = fmt::format("G{}{}", motion_code(p.motion), axes);
    if (arc) {
      const PlaneAxes pa = plane_axes(plane);
      for (int s : {pa.u, pa.v})
        l += fmt::format(" {}{}", static_cast<char>('I' + s),
                         number_text(aw.offset[static_cast<std::size_t>(s)], decimals_));
    }
    out_motion_ = motion_code(p.motion);
    return l;
  }

  std::string_view text_;
  const std::string& source_;
  const GcodeOptions& options_;
  std::span<const CorrectedMove> moves_;
  const GcodeRewriteOptions& ro_;
  std::vector<std::string_view> lines_;
  bool ends_with_newline_ = true;
  std::array<bool, 6> has_{};
  GcodePosition held_{}, next_held_{};  // what the controller holds, program units (mm, deg)
  int out_motion_ = -1;                 // the motion mode in effect in the output
  bool inches_ = false, incremental_ = false;
  int decimals_ = 6;
  std::string out_;
};

}  // namespace

std::string rewrite_gcode(std::string_view text, const std::string& source, const GcodeOptions& options,
                          std::span<const CorrectedMove> moves, const GcodeRewriteOptions& rewrite,
                          GcodeRewriteSummary* summary) {
  GcodeRewriteSummary local;
  Rewriter r(text, source, options, moves, rewrite);
  std::string out = r.run(summary ? *summary : local);
  return out;
}

std::string write_expanded_gcode(std::span<const CorrectedMove> moves, const GcodeProgram& program,
                                 const std::string& axes, const std::string& title, const GcodeRewriteOptions& ro,
                                 GcodeRewriteSummary* summary) {
  if (moves.size() != program.moves.size())
    throw Error(fmt::format("{}: {} corrected moves but the program has {} moves", program.source, moves.size(),
                            program.moves.size()));
  if (ro.decimals < 0 || ro.decimals > 12)
    throw InputError({"decimals", 0, ""},
                     fmt::format("expected 0 to 12 digits after the decimal point, found {}", ro.decimals));
  std::array<bool, 6> has{};
  for (char c : axes) {
    const int slot = axis_slot(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
    if (slot >= 0) has[static_cast<std::size_t>(slot)] = true;
  }
  std::string out;
  // A comment cannot hold parentheses (RS274NGC 3.3.4): those of a name become brackets.
  auto comment = [](std::string text) {
    for (char& c : text)
      if (c == '(')
        c = '[';
      else if (c == ')')
        c = ']';
      else if (c == '\n' || c == '\r')
        c = ' ';
    return text;
  };
  out += fmt::format("({})\n", comment(title));
  out += fmt::format("(from {}, read by {}: every move as it runs, canned cycles, G28/G30 and subroutines expanded)\n",
                     comment(program.source),
                     program.interpreter == "rs274" ? "LinuxCNC's interpreter rs274" : "mtcal's reader");
  out += "(absolute positions in mm and deg with the original's work offsets and tool lengths included:)\n";
  out += "(run with the program zero where the original's machine frame has it and no tool length offset, G49)\n";
  out += "(spindle, coolant and tool change commands are not written: add them before running)\n";
  out += "G21 G90 G94 G40 G49 G80 G17\n";
  std::size_t lines = 6;
  GcodePlane plane = GcodePlane::XY;
  double feed = -1;
  int tool = -2;
  auto put_axes = [&](std::string& row, const GcodePosition& p) {
    for (std::size_t s = 0; s < 6; ++s)
      if (has[s]) row += fmt::format(" {}{}", kGcodeAxes[s], number_text(p[s], ro.decimals));
  };
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const GcodeMove& original = program.moves[i];
    if (original.tool != tool) {
      tool = original.tool;
      if (tool >= 0) {
        out += fmt::format("(tool {} from here)\n", tool);
        ++lines;
      }
    }
    GcodePosition start = i == 0 ? original.start : GcodePosition{};
    if (i > 0) start = moves[i - 1].pieces.back().end;
    for (const CorrectedPiece& piece : moves[i].pieces) {
      std::string row;
      const bool arc = piece.motion == GcodeMotion::ArcCW || piece.motion == GcodeMotion::ArcCCW;
      if (arc && original.plane != plane) {
        plane = original.plane;
        row += std::string(to_string(plane)) + " ";
      }
      // An arc of more than a turn (LinuxCNC's P turns) goes out as arcs of at most one turn.
      const int parts =
          arc ? std::max(1, static_cast<int>(std::ceil(std::abs(piece.sweep) / (2 * std::numbers::pi) - 1e-9))) : 1;
      GcodeMove m;
      m.motion = piece.motion;
      m.plane = original.plane;
      m.start = start;
      m.end = piece.end;
      m.centre = piece.centre;
      m.sweep = piece.sweep;
      for (int k = 0; k < parts; ++k) {
        const GcodePosition a = k == 0 ? start : position_at(m, static_cast<double>(k) / parts);
        const GcodePosition b = k + 1 == parts ? piece.end : position_at(m, static_cast<double>(k + 1) / parts);
        std::string r = k == 0 ? row : std::string();
        r += fmt::format("G{}", motion_code(piece.motion));
        put_axes(r, b);
        if (arc) {
          const PlaneAxes pa = plane_axes(original.plane);
          for (int s : {pa.u, pa.v})
            r += fmt::format(" {}{}", static_cast<char>('I' + s),
                             number_text(piece.centre[static_cast<std::size_t>(s)] - a[static_cast<std::size_t>(s)],
                                         ro.decimals));
        }
        if (piece.motion != GcodeMotion::Rapid && original.feed != feed && original.feed > 0) {
          feed = original.feed;
          r += " F" + number_text(feed, ro.decimals > 3 ? 3 : ro.decimals);
        }
        r += fmt::format(" (line {})\n", original.line);
        out += r;
        ++lines;
      }
      start = piece.end;
    }
  }
  out += "M2\n";
  ++lines;
  if (summary) {
    summary->lines_in = program.counts.lines;
    summary->lines_changed = 0;
    summary->lines_added = lines;
  }
  return out;
}

CorrectedProgram corrected_program(const Machine& m, const GcodeProgram& program, std::string_view text,
                                   std::span<const CorrectedMove> moves, const GcodeRewriteOptions& rewrite) {
  CorrectedProgram c;
  c.expanded = program.interpreter != "mtcal" || program.counts.expanded_blocks > 0 || program.counts.offset_blocks > 0;
  std::string axes;
  for (const auto& ax : m.axes) axes += ax.letter;
  if (c.expanded) {
    c.text = write_expanded_gcode(moves, program, axes,
                                  fmt::format("mtcal compensate --gcode: corrected for machine {}", m.name), rewrite,
                                  &c.summary);
  } else {
    GcodeOptions go;
    go.axes = axes;
    c.text = rewrite_gcode(text, program.source, go, moves, rewrite, &c.summary);
  }
  return c;
}

}  // namespace mtcal
