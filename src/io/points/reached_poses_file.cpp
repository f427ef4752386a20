#include "mtcal/io/points/reached_poses_file.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "mtcal/io/system/files.hpp"
#include "mtcal/io/text/csv.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal {

std::vector<ReachedPose> parse_reached_poses(const Machine& m, const std::string& text, const std::string& source) {
  const CsvTable t = parse_csv(text, source);
  std::string linear, rotary;
  for (const auto& ax : m.axes) (ax.kind == AxisKind::Linear ? linear : rotary) += ax.letter;
  if (linear.size() != 3 || rotary.size() > 2)
    throw InputError({source, 0, ""}, "expected a machine with three linear axes and at most two rotary ones (the "
                                      "controller's world coordinates), found topology " + m.topology.chain);
  std::vector<std::string> wanted;
  for (char c : std::string("XYZABC"))
    if (m.axis_index(c)) wanted.push_back(std::string(1, c));
  std::string world;
  for (char c : std::string("XYZABC"))
    if (m.axis_index(c)) world += c;
  std::vector<int> world_col, joint_col(m.axes.size(), -1);
  for (char c : world) {
    const int w = t.column(std::string(1, c)), q = t.column(std::string("q") + c);
    if (w < 0 || q < 0)
      throw InputError({source, 1, w < 0 ? std::string(1, c) : std::string("q") + c},
                       fmt::format("expected the columns {} (commanded world pose, mm and deg) and q{} (joints "
                                   "reached), found no column '{}'",
                                   fmt::join(wanted, ","), fmt::join(wanted, ",q"),
                                   w < 0 ? std::string(1, c) : std::string("q") + c));
    world_col.push_back(w);
    joint_col[*m.axis_index(c)] = q;
  }
  for (const auto& name : t.columns) {
    const bool known = name == "pose" || (name.size() == 1 && world.find(name[0]) != std::string::npos) ||
                       (name.size() == 2 && name[0] == 'q' && world.find(name[1]) != std::string::npos);
    if (!known)
      throw InputError({source, 1, name},
                       fmt::format("unexpected column '{}' (expected {}, q{} and optionally pose)", printable(name),
                                   fmt::join(wanted, ","), fmt::join(wanted, ",q")));
  }
  std::vector<ReachedPose> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const auto& row = t.rows[r];
    ReachedPose p;
    p.line = t.lines[r];
    for (std::size_t k = 0; k < world.size(); ++k) {
      const double v = row[static_cast<std::size_t>(world_col[k])];
      const char c = world[k];
      if (c == 'X' || c == 'Y' || c == 'Z') {
        // The tool point: X, Y, Z along the workpiece frame's x, y, z.
        p.commanded.point[c - 'X'] = v;
      }
    }
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
      const double v = row[static_cast<std::size_t>(joint_col[k])];
      p.q.push_back(m.axes[k].kind == AxisKind::Rotary ? v * kRadPerDeg : v);
      if (m.axes[k].kind == AxisKind::Rotary)
        p.commanded.rotary.push_back(row[static_cast<std::size_t>(t.column(std::string(1, m.axes[k].letter)))] *
                                     kRadPerDeg);
    }
    out.push_back(std::move(p));
  }
  if (out.empty()) throw InputError({source, 0, ""}, "expected at least one pose, found none");
  return out;
}

std::vector<ReachedPose> read_reached_poses(const Machine& m, const std::string& path) {
  return parse_reached_poses(m, read_text_file(path, "reached-pose file"), path);
}

}  // namespace mtcal
