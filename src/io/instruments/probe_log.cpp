#include "mtcal/io/instruments/probe_log.hpp"

#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/kinematics/tool_point_coordinates.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {

namespace {

// Cells of a line: split at commas when it has any (ISO CSV), else at blanks.
std::vector<std::string> fields(std::string_view line, bool commas) {
  std::vector<std::string> out;
  if (commas && line.find(',') != std::string_view::npos) {
    std::size_t p = 0;
    for (;;) {
      const std::size_t c = line.find(',', p);
      out.emplace_back(line.substr(p, c == std::string_view::npos ? std::string_view::npos : c - p));
      if (c == std::string_view::npos) break;
      p = c + 1;
    }
    return out;
  }
  std::string cur;
  for (char ch : line) {
    if (ch == ' ' || ch == '\t' || ch == '\r') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

}  // namespace

std::vector<LoggedContact> parse_probe_log(const Machine& m, std::string_view text, const std::string& source,
                                           ProbeLogFormat format) {
  const bool iso = format == ProbeLogFormat::IsoCsv;
  // Column letters of the log in order, and where each goes in the machine's chain.
  const std::string letters = iso ? "XYZABC" : "XYZABCUVW";
  std::vector<std::size_t> at(letters.size(), m.axes.size());
  for (std::size_t c = 0; c < letters.size(); ++c)
    if (const auto k = m.axis_index(letters[c])) at[c] = *k;
  std::vector<LoggedContact> out;
  int line = 0;
  std::size_t pos = 0;
  bool first = true;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    if (iso) {
      if (const auto h = l.find(" #"); h != std::string_view::npos) l = l.substr(0, h);
      if (!l.empty() && l.front() == '#' && (l.size() < 2 || !std::isdigit(static_cast<unsigned char>(l[1])))) l = {};
    }
    if (trim(l).empty()) {
      if (end == text.size()) break;
      continue;
    }
    const auto f = fields(l, iso);
    if (iso && first && !f.empty() && !parse_number(trim(f[0]))) {  // a header of column names
      first = false;
      continue;
    }
    first = false;
    const std::size_t min = iso ? 3 : 9, max = iso ? 6 : 9;
    if (f.size() < min || f.size() > max)
      throw InputError({source, line, ""},
                       fmt::format("expected {} numbers ({}), found {}", iso ? "3 to 6" : "9",
                                   iso ? "#5061 #5062 #5063 [#5064 #5065 #5066]: X Y Z [A B C]"
                                       : "X Y Z A B C U V W, as LinuxCNC's PROBEOPEN log writes them",
                                   f.size()));
    LoggedContact c;
    c.q.assign(m.axes.size(), std::numeric_limits<double>::quiet_NaN());
    c.source = source;
    c.line = line;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto v = parse_number(trim(f[i]));
      if (!v)
        throw InputError({source, line, std::string(1, letters[i])},
                         fmt::format("expected a number for {}, found '{}'", letters[i], printable(f[i])));
      if (at[i] == m.axes.size()) continue;
      c.q[at[i]] = m.axes[at[i]].kind == AxisKind::Rotary ? *v * std::numbers::pi / 180.0 : *v;
    }
    out.push_back(std::move(c));
    if (end == text.size()) break;
  }
  // An empty log is a log of no contact: the caller, who knows how many it expects, names the first
  // one missing (a probe that never tripped stops LinuxCNC's program before its first line).
  return out;
}

std::vector<LoggedContact> read_probe_log(const Machine& m, const std::string& path, ProbeLogFormat format) {
  return parse_probe_log(m, read_text_file(path, "probe log"), path, format);
}

std::vector<LoggedContact> contacts_from_tool_points(const Machine& m, std::vector<LoggedContact> contacts) {
  std::optional<ToolPointCoordinates> world;
  try {
    world.emplace(m);
  } catch (const ModelError& e) {
    throw InputError({m.source, 0, ""}, std::string("no tool-point coordinates for this machine: ") + e.what());
  }
  for (LoggedContact& c : contacts) {
    for (std::size_t k = 0; k < m.axes.size(); ++k)
      if (!std::isfinite(c.q[k]))
        throw InputError({c.source, c.line, ""},
                         fmt::format("expected a value of {} (tool-point coordinates need every axis of the machine), "
                                     "found none",
                                     m.axes[k].letter));
    c.q = world->axes(c.q);
  }
  return contacts;
}

}  // namespace mtcal
