#include "mtcal/io/gcode/probe_program.hpp"

#include <algorithm>
#include <functional>
#include <cmath>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/kinematics/tool_point_coordinates.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

// "X12.345000 Y-3.000000 Z40.000000" for the given axes of q (mm; deg for rotary axes).
std::string words(const Machine& m, const std::vector<double>& q, bool rotary) {
  std::string out;
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    if ((m.axes[k].kind == AxisKind::Rotary) != rotary) continue;
    const double v = rotary ? q[k] * 180.0 / std::numbers::pi : q[k];
    out += fmt::format("{}{}{:.6f}", out.empty() ? "" : " ", m.axes[k].letter, std::abs(v) < 5e-7 ? 0.0 : v);
  }
  return out;
}

// What differs between the plan's program and the locating one: its title and cycle comment lines
// (functions of the safe retract's axis letter and level), and how far above a ball's target its
// touches change over (along the tool axis).
struct ProgramKind {
  std::string title;  // "probing program", "locating program"
  std::function<std::string(char, double)> cycle_line;
  double top_above = 0.0;
  // The cycle whose clearance level the G0 down before a record's first touch stops at
  // (probe_clearance_level); the locating program's clearance includes its search distance.
  ProbeCycle cycle;
};

std::string program_text(const Machine& m, const ProbingPlan& plan, const std::vector<ProbeTouch>& touches,
                         const ProgramKind& kind, const ProbeProgramOptions& o) {
  for (const auto& [name, v] : {std::pair{"probing feed", o.probe_feed}, std::pair{"feed", o.feed}})
    if (!(v > 0) || !std::isfinite(v)) throw InputError({name, 0, ""}, fmt::format("expected > 0 mm/min, found {:g}", v));
  if (o.log.find_first_of("()\n\r") != std::string::npos)
    throw InputError({"probe log", 0, o.log}, "a log file name may not contain parentheses or line ends");
  const bool tcp = o.coordinates == ProbeCoordinates::ToolPoint;
  if (tcp && !(o.index_step > 0 && std::isfinite(o.index_step)))
    throw InputError({"indexing step", 0, ""}, fmt::format("expected > 0 rad, found {:g}", o.index_step));
  std::optional<ToolPointCoordinates> world;
  if (tcp) {
    try {
      world.emplace(m);
    } catch (const ModelError& e) {
      throw InputError({m.source, 0, ""}, std::string("no tool-point coordinates for this machine: ") + e.what());
    }
  }
  // The words of a position: the axis values themselves, or their tool point's world position.
  const auto at = [&](const std::vector<double>& q, bool rotary) { return words(m, tcp ? world->world(q) : q, rotary); };
  const auto full = [&](const std::vector<double>& q) { return at(q, false) + (tcp ? " " + at(q, true) : ""); };
  const bool lcnc = o.dialect == ProbeDialect::LinuxCNC;
  // The tool-axis linear axis and its safe end: where the tool is farthest from the workpiece.
  std::size_t tz = m.axes.size();
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    if (m.axes[k].kind == AxisKind::Linear && m.axes[k].direction_axis == m.tool.tool_axis) tz = k;
  if (tz == m.axes.size() || !m.axes[tz].travel)
    throw InputError({m.source, 0, ""}, "the linear axis along the tool needs a travel (its end is the safe retract)");
  const Axis& zax = m.axes[tz];
  const double safe = zax.direction_sign > 0 ? zax.travel->max : zax.travel->min;
  const char zl = zax.letter;

  std::string s;
  if (!lcnc) s += "%\n";
  s += fmt::format("(mtcal {}, {} dialect: {} records, {} probing moves)\n", kind.title, lcnc ? "LinuxCNC" : "ISO",
                   plan.records.size(), touches.size());
  // A comment ends at the first ')' and LinuxCNC refuses a '(' inside one ("Nested comment found",
  // met with the example machines' names): brackets instead, line ends as blanks.
  std::vector<std::string> lines;
  if (!o.header.empty()) lines.push_back(o.header);
  lines.insert(lines.end(), o.notes.begin(), o.notes.end());
  for (std::string h : lines) {
    for (char& c : h) c = c == '(' ? '[' : c == ')' ? ']' : (c == '\n' || c == '\r') ? ' ' : c;
    s += "(" + h + ")\n";
  }
  if (tcp) {
    s += "(Coordinates: tool-point world of a tool-centre-point kinematics - X Y Z the nominal tool point in the "
         "workpiece frame, mm; rotary words the rotary axes, deg; the tool length is in the model and the kinematics.)\n";
    s += "(Indexations turn at the safe level in blocks that hold the linear axes there.)\n";
  } else {
    s += "(Coordinates: the machine's axis values of mtcal's model, mm and deg; the tool length is in the model.)\n";
  }
  s += "(Run with the G54 work offsets zero and no tool length offset: G54 G49 below.)\n";
  s += kind.cycle_line(zl, safe);
  if (lcnc)
    s += "(Each G38.2 contact is logged by LinuxCNC to the PROBEOPEN file: X Y Z A B C U V W a line.)\n";
  else
    s += "(After each G31 record the skip position #5061 #5062 #5063 as one CSV line, in order: mtcal reads that file.)\n";
  s += "G21 G90 G94 G17 G40 G49 G54 G80\n";
  if (lcnc) s += fmt::format("(PROBEOPEN {})\n", o.log);
  const std::size_t none = plan.records.size();
  std::size_t current = none;
  std::vector<double> last_rotary;
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const ProbeTouch& t = touches[i];
    const ProbingRecord& r = plan.records[t.record];
    const bool ball = plan.features[r.feature].kind == ProbeFeature::Kind::Ball;
    if (t.record != current) {
      current = t.record;
      s += fmt::format("(record {}: indexation {}, {} {}, plan line {})\n", t.record + 1, r.indexation,
                       ball ? "ball" : "facet", plan.features[r.feature].id, r.line);
      // Over the start at the safe level, down at rapid to the clearance level, then the rest at the feed.
      std::vector<double> over = t.start;
      over[tz] = safe;
      if (!tcp) {
        s += fmt::format("G0 {}{:.6f}\n", zl, safe);
        const std::string rot = words(m, r.q, true);
        if (!rot.empty() && rot != (last_rotary.empty() ? std::string() : words(m, last_rotary, true)))
          s += "G0 " + rot + "\n";
      } else {
        // Up to the safe level where the last touch started (the first record: from the rotary
        // zero at the safe level), then the indexation along the axes' own path.
        std::vector<double> from = i == 0 ? std::vector<double>(m.axes.size(), 0.0) : touches[i - 1].start;
        from[tz] = safe;
        s += "G0 " + full(from) + "\n";
        double turn = 0;
        for (std::size_t k = 0; k < m.axes.size(); ++k)
          if (m.axes[k].kind == AxisKind::Rotary) turn = std::max(turn, std::abs(r.q[k] - from[k]));
        const auto steps = static_cast<std::size_t>(std::ceil(turn / o.index_step - 1e-9));
        for (std::size_t j = 1; j <= steps; ++j) {
          std::vector<double> q = from;
          for (std::size_t k = 0; k < m.axes.size(); ++k)
            if (m.axes[k].kind == AxisKind::Rotary)
              q[k] = from[k] + (r.q[k] - from[k]) * static_cast<double>(j) / static_cast<double>(steps);
          s += "G0 " + full(q) + "\n";
        }
      }
      last_rotary = r.q;
      s += "G0 " + at(over, false) + "\n";
      // Down at rapid to the clearance level; only the last of the approach at the move feed.
      std::vector<double> down = t.start;
      down[tz] = probe_clearance_level(m, plan, r, t, kind.cycle);
      s += "G0 " + at(down, false) + "\n";
    } else if (ball) {
      // Between a ball's touches: up to the clearance level above the ball, over, down.
      std::vector<double> lift = touches[i - 1].start, over = t.start;
      const double top = r.q[tz] + zax.direction_sign * kind.top_above;
      lift[tz] = top;
      over[tz] = top;
      s += fmt::format("G1 {} F{:g}\n", at(lift, false), o.feed);
      s += fmt::format("G1 {} F{:g}\n", at(over, false), o.feed);
    }
    s += fmt::format("G1 {} F{:g}\n", at(t.start, false), o.feed);
    s += fmt::format("{} {} F{:g}\n", lcnc ? "G38.2" : "G31", at(t.end, false), o.probe_feed);
    s += fmt::format("G1 {} F{:g}\n", at(t.start, false), o.feed);
  }
  if (!tcp || touches.empty()) {
    s += fmt::format("G0 {}{:.6f}\n", zl, safe);
  } else {
    std::vector<double> end = touches.back().start;
    end[tz] = safe;
    s += "G0 " + at(end, false) + "\n";
  }
  if (lcnc) s += "(PROBECLOSE)\n";
  s += "M2\n";
  if (!lcnc) s += "%\n";
  return s;
}

}  // namespace

std::string probe_program(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                          const ProbeProgramOptions& o) {
  ProgramKind kind;
  kind.title = "probing program";
  kind.cycle_line = [&](char zl, double safe) {
    return fmt::format("(Cycle: ball diameter {:g} mm, tip diameter {:g} mm, approach {:g} mm, overtravel {:g} mm, "
                       "clearance {:g} mm, {} touches a ball; safe retract {}{:g})\n",
                       cycle.ball_diameter, cycle.tip_diameter, cycle.approach, cycle.overtravel, cycle.clearance,
                       cycle.touches_per_ball, zl, safe);
  };
  kind.top_above = (cycle.ball_diameter + cycle.tip_diameter) / 2 + cycle.clearance;
  kind.cycle = cycle;
  return program_text(m, plan, probe_touches(m, plan, cycle), kind, o);
}

std::string locate_program(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                           const LocateOptions& locate, const ProbeProgramOptions& o) {
  const auto touches = locate_touches(m, plan, cycle, locate);
  ProgramKind kind;
  kind.title = "locating program";
  kind.cycle_line = [&](char zl, double safe) {
    return fmt::format("(Locating cycle: each ball's centre within {:g} mm of its rough position; ball diameter {:g} "
                       "mm, tip diameter {:g} mm, approach {:g} mm, overtravel {:g} mm, clearance {:g} mm; {} touches "
                       "a ball - the pole, 4 on the equator, 4 above it; safe retract {}{:g})\n",
                       locate.within, cycle.ball_diameter, cycle.tip_diameter, cycle.approach, cycle.overtravel,
                       cycle.clearance, plan.records.empty() ? 0 : touches.size() / plan.records.size(), zl, safe);
  };
  kind.top_above = (cycle.ball_diameter + cycle.tip_diameter) / 2 + locate.within + cycle.clearance;
  kind.cycle = cycle;
  kind.cycle.clearance += locate.within;
  return program_text(m, plan, touches, kind, o);
}

void write_locate_program(const std::string& path, const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                          const LocateOptions& locate, const ProbeProgramOptions& options) {
  write_file_atomically(path, locate_program(m, plan, cycle, locate, options));
}

void write_probe_program(const std::string& path, const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                         const ProbeProgramOptions& options) {
  write_file_atomically(path, probe_program(m, plan, cycle, options));
}

}  // namespace mtcal
