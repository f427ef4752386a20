#include "mtcal/io/compensation/linuxcnc.hpp"

#include <fmt/format.h>

namespace mtcal {

TargetOutput linuxcnc_output(const LinuxcncCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  for (const auto& t : c.tables) {
    std::string text;
    for (std::size_t i = 0; i < t.nominal.size(); ++i)
      text += fmt::format("{:.9f} {:.9f} {:.9f}\n", t.nominal[i], t.forward[i], t.reverse[i]);
    out.files.push_back({std::string(1, t.axis) + ".comp", std::move(text)});
  }
  std::string ini = fmt::format(
      "# Written by mtcal compensate --format linuxcnc: merge these sections into the machine's INI file.\n"
      "# COMP_FILE_TYPE {}: the columns are {} (LinuxCNC usrmotintf.cc, usrmotLoadComp()).\n"
      "# Joint n is the n-th of COORDINATES; tables are in joint units (mm, deg).\n",
      c.comp_file_type,
      c.comp_file_type == 0 ? "the positions actually reached, nominal + error; the controller adds nominal - column"
                            : "corrections, -error, added to the motor command");
  if (!c.kinematics.empty()) {
    std::string coords;
    for (const char l : c.coordinates) coords += std::string(coords.empty() ? "" : " ") + l;
    ini += "\n[KINS]\n";
    ini += c.kinematics == "trivkins" ? fmt::format("KINEMATICS = trivkins coordinates={}\n", c.coordinates)
                                      : fmt::format("KINEMATICS = {}\n", c.kinematics);
    ini += fmt::format("JOINTS = {}\n\n[TRAJ]\nCOORDINATES = {}\n", c.coordinates.size(), coords);
  }
  if (!c.pins.empty()) {
    ini += "\n[HAL]\nHALFILE = linuxcnc-kins.hal\n";
    std::string hal = fmt::format(
        "# Written by mtcal compensate --format linuxcnc: the rotary axis lines of {} (mm, relative to the tool\n"
        "# point with every joint at zero; src/emc/kinematics/trtfuncs.c).\n",
        c.kinematics);
    for (const auto& p : c.pins) hal += fmt::format("setp {} {:.9f}\n", p.name, p.value);
    out.files.push_back({"linuxcnc-kins.hal", std::move(hal)});
  }
  for (const auto& t : c.tables)
    ini += fmt::format("\n[JOINT_{}]\nCOMP_FILE = {}.comp\nCOMP_FILE_TYPE = {}\n", t.joint, t.axis, c.comp_file_type);
  out.files.push_back({"linuxcnc.ini", std::move(ini)});
  return out;
}

}  // namespace mtcal
