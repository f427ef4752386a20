// Readers and writers of the probing files (io/instruments/probing_files.hpp).
#include "mtcal/io/instruments/probing_files.hpp"
#include "mtcal/util/units.hpp"

#include <algorithm>
#include <map>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {


void refuse_unknown_columns(const CsvTable& t, const std::string& file, const std::vector<std::string>& allowed) {
  for (const auto& c : t.columns)
    if (std::find(allowed.begin(), allowed.end(), c) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw InputError({file, 1, c}, "unknown column '" + c + "' (expected " + list + ")");
    }
}

std::size_t require(const CsvTable& t, const std::string& file, const std::string& name) {
  const int c = t.column(name);
  if (c < 0) throw InputError({file, 1, ""}, "missing column '" + name + "'");
  return static_cast<std::size_t>(c);
}

std::vector<std::string> axis_columns() { return {"X", "Y", "Z", "A", "B", "C"}; }

}  // namespace

ContactSet read_contacts_csv(const std::string& path, char axis) {
  return parse_contacts_csv(read_text_file(path, "CSV file"), path, axis);
}

ContactSet parse_contacts_csv(const std::string& text, const std::string& path, char axis) {
  const CsvTable t = parse_csv(text, path);
  auto allowed = axis_columns();
  for (const char* c : {"x", "y", "z", "approach_x", "approach_y", "approach_z"}) allowed.push_back(c);
  refuse_unknown_columns(t, path, allowed);
  const std::size_t ca = require(t, path, std::string(1, axis));
  const std::size_t cx = require(t, path, "x"), cy = require(t, path, "y"), cz = require(t, path, "z");
  const int ax = t.column("approach_x"), ay = t.column("approach_y"), az = t.column("approach_z");
  const bool approach = ax >= 0 && ay >= 0 && az >= 0;
  if (!approach && (ax >= 0 || ay >= 0 || az >= 0))
    throw InputError({path, 1, ""}, "give all three approach_x, approach_y, approach_z columns or none");
  ContactSet set;
  set.source = path;
  set.axis = axis;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    IndexedContact c;
    c.angle_deg = row[ca];
    c.line = t.lines[r];
    c.contact.point = Point3(row[cx], row[cy], row[cz]);
    if (approach) {
      c.contact.approach = Point3(row[static_cast<std::size_t>(ax)], row[static_cast<std::size_t>(ay)],
                                  row[static_cast<std::size_t>(az)]);
      if (!(c.contact.approach.norm() > 0))
        throw InputError({path, t.lines[r], "approach_x"}, "the approach direction is a zero vector");
      c.contact.approach.normalize();
    }
    set.contacts.push_back(c);
  }
  return set;
}

IndexedCentres read_centres_csv(const std::string& path, char axis) {
  return parse_centres_csv(read_text_file(path, "CSV file"), path, axis);
}

IndexedCentres parse_centres_csv(const std::string& text, const std::string& path, char axis) {
  const CsvTable t = parse_csv(text, path);
  auto allowed = axis_columns();
  for (const char* c : {"x", "y", "z"}) allowed.push_back(c);
  refuse_unknown_columns(t, path, allowed);
  const std::string letter(1, axis);
  const std::size_t ca = require(t, path, letter);
  const std::size_t cx = require(t, path, "x"), cy = require(t, path, "y"), cz = require(t, path, "z");
  IndexedCentres out;
  out.source = path;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    const double angle = row[ca];  // an angle given twice is one position measured twice: averaged later
    out.centres.push_back({angle * kRadPerDeg, Point3(row[cx], row[cy], row[cz])});
  }
  return out;
}

std::string contacts_csv(const Axis& axis, const std::vector<ProbedIndexation>& probed) {
  std::string s = std::string(1, axis.letter) + ",x,y,z,approach_x,approach_y,approach_z\n";
  for (const auto& ix : probed)
    for (const auto& c : ix.contacts)
      s += fmt::format("{:.12g},{:.9f},{:.9f},{:.9f},{:g},{:g},{:g}\n", to_user_units(axis, ix.angle), c.point.x(),
                       c.point.y(), c.point.z(), c.approach.x(), c.approach.y(), c.approach.z());
  return s;
}

void write_contacts_csv(const std::string& path, const Axis& axis, const std::vector<ProbedIndexation>& probed) {
  write_file_atomically(path, contacts_csv(axis, probed));
}

std::string rotary_parameters_yaml(const RotaryAxisResult& result) {
  const RotaryEstimate& use = result.best();
  const auto names = rotary_quantity_names(result.axis.letter);
  std::string y = fmt::format("# Location errors of axis {} from mtcal rotary-axis ({}), {} indexations of {}\n",
                              result.axis.letter, result.least_squares ? "least squares" : "triples",
                              result.centres.centres.size(), result.centres.source);
  y += "mtcal_parameters: 1\nerrors:\n";
  for (std::size_t q = 0; q < 4; ++q)
    y += fmt::format("  {}: {{value: {:.17g}, unit: {}}}  # +- {:.3g} (standard uncertainty)\n", names[q], use.value[q],
                     q < 2 ? "mm" : "rad", use.uncertainty[q]);
  return y;
}

void write_rotary_parameters(const std::string& path, const RotaryAxisResult& result) {
  write_file_atomically(path, rotary_parameters_yaml(result));
}

}  // namespace mtcal
