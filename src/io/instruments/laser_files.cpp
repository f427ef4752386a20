// Renishaw LaserXL / CARTO ASCII exports (io/instruments/laser_files.hpp), written from the published
// description of the sections; no public sample file was available (docs/instrument-files.md).
#include "mtcal/io/instruments/laser_files.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

bool ends_with(const std::string& s, std::string_view e) {
  return s.size() >= e.size() && to_lower(s.substr(s.size() - e.size())) == e;
}

// Whitespace- or comma-separated tokens.
std::vector<std::string> tokens(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      if (!cur.empty()) out.push_back(cur), cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

const std::vector<std::string> kSections = {"HEADER",     "TARGET DATA", "USER-TEXT", "RUNS",
                                            "DEVIATIONS", "ENVIRONMENT", "EQUIPMENT"};

struct Reader {
  explicit Reader(const std::string& s) : source(s) {}
  const std::string& source;
  LaserFile out;
  std::string target_unit, deviation_unit;
  int target_unit_line = 0, deviation_unit_line = 0;
  std::optional<long> target_count, run_count;
  int target_count_line = 0, run_count_line = 0, targets_line = 0, deviations_line = 0;
  std::vector<double> targets;
  bool reading_targets = false, reading_rows = false;
  std::map<long, std::map<long, std::pair<double, int>>> rows;  // run -> target -> (deviation, line)

  // A number with an optional unit glued or spaced after it ("100.0", "1.2um", "1.2 um"), the
  // unit checked against the declared one: a file mixing units is refused, not converted.
  double value(const std::string& cell, const std::string& unit, int line, const std::string& field) {
    std::size_t k = 0;
    while (k < cell.size() && (std::isdigit(static_cast<unsigned char>(cell[k])) || cell[k] == '.' || cell[k] == '-' ||
                               cell[k] == '+' || cell[k] == 'e' || cell[k] == 'E'))
      ++k;
    const auto v = parse_number(cell.substr(0, k));
    const std::string suffix = trim(cell.substr(k));
    if (!v) throw InputError({source, line, field}, "expected a number, found '" + printable(cell) + "'");
    if (!suffix.empty()) {
      const auto u = find_unit(suffix), declared = find_unit(unit);
      if (!u || !declared || u->name != declared->name)
        throw InputError({source, line, field},
                         fmt::format("mixed units: '{}' is in {}, the file's {} are in {}", printable(cell),
                                     printable(suffix), field == "Targets" ? "targets" : "deviations", unit));
    }
    return *v;
  }

  void key_value(const std::string& section, const std::string& key, const std::string& value, int line) {
    const std::string k = to_lower(key);
    if (section == "TARGET DATA" && k == "target-count") {
      const auto v = parse_number(value);
      if (!v || *v != std::floor(*v) || *v < 1 || *v > 1e6)
        throw InputError({source, line, "Target-count"},
                         "expected a whole number >= 1, found '" + printable(value) + "'");
      target_count = static_cast<long>(*v), target_count_line = line;
    } else if (section == "TARGET DATA" && k == "targets") {
      targets_line = line;
      reading_targets = true;
      for (const auto& t : tokens(value)) targets.push_back(this->value(t, target_unit, line, "Targets"));
    } else if (section == "RUNS" && k == "run-count") {
      const auto v = parse_number(value);
      if (!v || *v != std::floor(*v) || *v < 1 || *v > 1e6)
        throw InputError({source, line, "Run-count"}, "expected a whole number >= 1, found '" + printable(value) + "'");
      run_count = static_cast<long>(*v), run_count_line = line;
    } else if (section == "RUNS" && k == "direction") {
      const std::string d = to_lower(value);
      if (d.rfind("uni", 0) == 0)
        out.bidirectional = false;
      else if (d.rfind("bi", 0) == 0)
        out.bidirectional = true;
      else
        throw InputError({source, line, "Direction"},
                         "expected bidirectional or unidirectional, found '" + printable(value) + "'");
    } else if (section == "DEVIATIONS" && k == "run target data") {
      deviations_line = line;
      reading_rows = true;
      if (!trim(value).empty()) row(value, line);
    } else if (section == "HEADER" && (k == "target units" || k == "deviation units")) {
      const auto u = find_unit(trim(value));
      if (!u) throw InputError({source, line, key}, "unknown unit '" + printable(value) + "'");
      (k == "target units" ? target_unit : deviation_unit) = u->name;
      (k == "target units" ? target_unit_line : deviation_unit_line) = line;
    } else if ((section == "HEADER" || section == "USER-TEXT") && k == "type") {
      const std::string t = to_lower(trim(value));
      if (t != "linear" && t != "rotary" && t != "straightness" && t != "angular")
        throw InputError({source, line, key},
                         "expected Linear, Rotary, Straightness or Angular, found '" + printable(value) + "'");
      out.kind = t;
      // The test's kind sets the default units where the header does not give them.
      if (target_unit_line == 0) target_unit = t == "rotary" ? "deg" : "mm";
      if (deviation_unit_line == 0) deviation_unit = t == "rotary" || t == "angular" ? "arcsec" : "um";
    } else if ((section == "HEADER" || section == "USER-TEXT") && (k == "error" || k == "component")) {
      out.component = to_upper(trim(value));
    } else if (section == "USER-TEXT" && k == "axis") {
      out.axis = to_upper(trim(value));
    } else if (section == "TARGET DATA" || section == "RUNS" || section == "DEVIATIONS") {
      out.runs.warnings.push_back(fmt::format("{}:{}: key '{}' of section {} is not used; kept as metadata", source,
                                              line, printable(key), section));
    }
    out.runs.metadata.emplace_back(section + "/" + printable(trim(key), 80), printable(trim(value), 200));
  }

  void row(const std::string& s, int line) {
    const auto t = tokens(s);
    if (t.size() != 3)
      throw InputError({source, line, "Run Target Data"},
                       fmt::format("expected 3 cells (run, target, deviation), found {}", t.size()));
    auto whole = [&](const std::string& cell, const char* field) {
      const auto v = parse_number(cell);
      if (!v || *v != std::floor(*v) || *v < 1 || *v > 1e9)
        throw InputError({source, line, field}, "expected a whole number >= 1, found '" + printable(cell) + "'");
      return static_cast<long>(*v);
    };
    const long run = whole(t[0], "Run"), target = whole(t[1], "Target");
    const double d = value(t[2], deviation_unit, line, "Deviation");
    if (run_count && run > *run_count)
      throw InputError({source, line, "Run"},
                       fmt::format("run {} beyond Run-count {} (line {})", run, *run_count, run_count_line));
    if (target_count && target > *target_count)
      throw InputError({source, line, "Target"}, fmt::format("target {} beyond Target-count {} (line {})", target,
                                                             *target_count, target_count_line));
    auto [it, fresh] = rows[run].try_emplace(target, d, line);
    if (!fresh)
      throw InputError({source, line, "Run Target Data"},
                       fmt::format("run {}, target {} given twice (first on line {})", run, target, it->second.second));
  }
};

}  // namespace

LaserFile parse_laser_file(const std::string& text, const std::string& source, bool rotary) {
  Reader r{source};
  r.target_unit = rotary ? "deg" : "mm";
  r.deviation_unit = rotary ? "arcsec" : "um";
  r.out.kind = rotary ? "rotary" : "linear";
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line, section;
  int lineno = 0;
  bool any_section = false;
  while (std::getline(in, line)) {
    ++lineno;
    const std::string s = trim(line);
    if (s.empty()) continue;
    if (s.size() > 2 && s.substr(s.size() - 2) == "::") {
      section = to_upper(trim(s.substr(0, s.size() - 2)));
      any_section = true;
      r.reading_targets = r.reading_rows = false;
      if (std::find(kSections.begin(), kSections.end(), section) == kSections.end())
        r.out.runs.warnings.push_back(fmt::format("{}:{}: section {} is not known; its lines are kept as metadata",
                                                  source, lineno, printable(section)));
      continue;
    }
    if (!any_section)
      throw InputError({source, lineno, ""}, "expected a section line such as HEADER:: before '" + printable(s) + "'");
    const auto colon = s.find(':');
    // Rows of numbers continue the Targets list or the Run Target Data table.
    const bool numeric_start =
        std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '-' || s[0] == '+' || s[0] == '.';
    if (numeric_start && r.reading_targets) {
      for (const auto& t : tokens(s)) r.targets.push_back(r.value(t, r.target_unit, lineno, "Targets"));
      continue;
    }
    if (numeric_start && r.reading_rows) {
      r.row(s, lineno);
      continue;
    }
    if (colon == std::string::npos) {
      if (section == "HEADER" || section == "USER-TEXT" || section == "ENVIRONMENT" || section == "EQUIPMENT" ||
          std::find(kSections.begin(), kSections.end(), section) == kSections.end()) {
        r.out.runs.metadata.emplace_back(section + "/", printable(s, 200));  // a free text line
        continue;
      }
      throw InputError({source, lineno, section}, "expected 'key: value', found '" + printable(s) + "'");
    }
    r.reading_targets = r.reading_rows = false;
    r.key_value(section, trim(s.substr(0, colon)), trim(s.substr(colon + 1)), lineno);
  }
  // Mandatory fields, then the counts against the data.
  if (!r.target_count) throw InputError({source, 0, "Target-count"}, "missing (section TARGET DATA::)");
  if (r.targets_line == 0) throw InputError({source, 0, "Targets"}, "missing (section TARGET DATA::)");
  if (!r.run_count) throw InputError({source, 0, "Run-count"}, "missing (section RUNS::)");
  if (r.deviations_line == 0) throw InputError({source, 0, "Run Target Data"}, "missing (section DEVIATIONS::)");
  if (static_cast<long>(r.targets.size()) != *r.target_count)
    throw InputError({source, r.targets_line, "Targets"},
                     fmt::format("{} targets given, Target-count (line {}) says {}", r.targets.size(),
                                 r.target_count_line, *r.target_count));
  if (*r.target_count < 2)
    throw InputError({source, r.target_count_line, "Target-count"}, "expected at least 2 targets");
  const auto tu = find_unit(r.target_unit), du = find_unit(r.deviation_unit);
  const bool angular_targets = tu && tu->dimension == Dimension::Angle;
  if ((r.out.kind == "rotary") != angular_targets)
    throw InputError({source, r.target_unit_line, "Target units"},
                     fmt::format("mixed units: a {} test with targets in {}", r.out.kind, r.target_unit));
  const bool angular_deviations = du && du->dimension == Dimension::Angle;
  if ((r.out.kind == "rotary" || r.out.kind == "angular") != angular_deviations)
    throw InputError({source, r.deviation_unit_line, "Deviation units"},
                     fmt::format("mixed units: a {} test with deviations in {}", r.out.kind, r.deviation_unit));
  for (long run = 1; run <= *r.run_count; ++run) {
    const auto it = r.rows.find(run);
    if (it == r.rows.end())
      throw InputError({source, r.deviations_line, "Run Target Data"},
                       fmt::format("run {} of Run-count {} has no data", run, *r.run_count));
    for (long t = 1; t <= *r.target_count; ++t)
      if (!it->second.count(t)) {
        int last = 0;
        for (const auto& [k, v] : it->second) last = std::max(last, v.second);
        throw InputError({source, last, "Run Target Data"},
                         fmt::format("run {} lacks target {} ({:g} {})", run, t,
                                     r.targets[static_cast<std::size_t>(t - 1)], r.target_unit));
      }
  }
  PositioningRuns& runs = r.out.runs;
  runs.source = source;
  runs.deviations = true;
  runs.unit = r.deviation_unit;
  runs.target_unit = r.target_unit;
  // Runs alternate: the odd ones approach each target moving in the order the targets are listed.
  const bool listed_up = r.targets.back() > r.targets.front();
  std::vector<std::size_t> order(r.targets.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return r.targets[a] < r.targets[b]; });
  for (std::size_t i : order) {
    std::vector<double> up, down;
    for (long run = 1; run <= *r.run_count; ++run) {
      const bool odd = run % 2 == 1;
      const bool moving_up = !r.out.bidirectional || odd ? listed_up : !listed_up;
      const double d = r.rows[run][static_cast<long>(i) + 1].first;
      (moving_up ? up : down).push_back(d);
    }
    runs.targets.push_back(r.targets[i]);
    runs.up.push_back(std::move(up));
    runs.down.push_back(std::move(down));
  }
  for (std::size_t k = 1; k < runs.targets.size(); ++k)
    if (runs.targets[k] == runs.targets[k - 1])
      throw InputError({source, r.targets_line, "Targets"},
                       fmt::format("target {:g} is listed twice", runs.targets[k]));
  return r.out;
}

LaserFile read_laser_file(const std::string& path) {
  return parse_laser_file(read_text_file(path, "laser file"), path, ends_with(path, ".rta"));
}

bool looks_like_laser(const std::string& path) {
  if (ends_with(path, ".rtl") || ends_with(path, ".rta")) return true;
  const std::string text = read_text_file(path, "positioning file");
  const std::string head = text.substr(0, 4096);
  return head.find("HEADER::") != std::string::npos;
}

std::string laser_error_name(const LaserFile& f) {
  if (!f.component.empty()) return f.component;
  if (f.axis.size() != 1) return "";
  if (f.kind == "linear" || f.kind == "rotary") return "E" + f.axis + f.axis;
  return "";
}

ReportMetadata laser_report_metadata(const PositioningRuns& runs) {
  // (section or "" for USER-TEXT and HEADER alike, key in lower case) -> field.
  struct Map {
    std::string_view section, key, field;
  };
  static constexpr Map kMap[] = {
      {"", "machine", "machine"},
      {"", "serial", "serial"},
      {"", "serial number", "serial"},
      {"", "machine serial", "serial"},
      {"", "owner", "owner"},
      {"", "customer", "owner"},
      {"", "location", "location"},
      {"", "operator", "operator"},
      {"", "date", "date"},
      {"", "test date", "date"},
      {"", "axis", "axis"},
      {"ENVIRONMENT", "air temperature", "temperature_air"},
      {"ENVIRONMENT", "machine temperature", "temperature_machine"},
      {"ENVIRONMENT", "material temperature", "temperature_material"},
      {"ENVIRONMENT", "temperature", "temperature"},
      {"ENVIRONMENT", "humidity", "humidity"},
      {"EQUIPMENT", "laser", "instrument"},
      {"EQUIPMENT", "instrument", "instrument"},
      {"EQUIPMENT", "serial", "instrument_serial"},
      {"EQUIPMENT", "serial number", "instrument_serial"},
      {"EQUIPMENT", "calibration date", "calibration_date"},
      {"EQUIPMENT", "calibration certificate", "calibration_certificate"},
      {"EQUIPMENT", "certificate", "calibration_certificate"},
  };
  ReportMetadata m;
  std::string extra_equipment;
  for (const auto& [full, value] : runs.metadata) {
    const auto slash = full.find('/');
    if (slash == std::string::npos || trim(value).empty()) continue;
    const std::string section = full.substr(0, slash), key = to_lower(trim(full.substr(slash + 1)));
    if (key.empty()) continue;  // a free text line
    const bool user = section == "USER-TEXT" || section == "HEADER";
    bool mapped = false;
    for (const auto& e : kMap)
      if (e.key == key && (e.section.empty() ? user : e.section == section)) {
        if (!m.get(e.field)) m.set(std::string(e.field), value, runs.source);
        mapped = true;
        break;
      }
    if (!mapped && section == "EQUIPMENT")
      extra_equipment += (extra_equipment.empty() ? "" : "; ") + full.substr(slash + 1) + " " + value;
  }
  if (!extra_equipment.empty()) {
    const std::string* instrument = m.get("instrument");
    m.set("instrument", instrument ? *instrument + "; " + extra_equipment : extra_equipment, runs.source);
  }
  return m;
}

}  // namespace mtcal
