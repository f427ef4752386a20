#include "mtcal/io/compensation/output.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "mtcal/io/compensation/etalon.hpp"
#include "mtcal/io/compensation/fanuc.hpp"
#include "mtcal/io/compensation/firmware.hpp"
#include "mtcal/io/compensation/heidenhain.hpp"
#include "mtcal/io/compensation/isg.hpp"
#include "mtcal/io/compensation/linuxcnc.hpp"
#include "mtcal/io/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/compensation/siemens.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace fs = std::filesystem;

const std::vector<CompensationTarget>& compensation_targets() {
  // Each target family adds its entries here (io/compensation_<family>.hpp).
  static const std::vector<CompensationTarget> targets = {
      {"linuxcnc", "LinuxCNC: COMP_FILE per linear joint (type 0 or 1), INI snippet, trt-kins pins",
       [](const Machine& m, const CompensationOptions& o) { return linuxcnc_output(compensate_linuxcnc(m, o)); }},
      {"linuxcnc-kins",
       "LinuxCNC kinematics module (C) applying the whole error model in the controller; reversal in COMP_FILEs",
       [](const Machine& m, const CompensationOptions& o) {
         return linuxcnc_kins_output(compensate_linuxcnc_kins(m, o));
       }},
      {"siemens", "Siemens SINUMERIK: %_N_AX_EEC_INI per linear axis, %_N_NC_CEC_INI sag/straightness/squareness tables",
       [](const Machine& m, const CompensationOptions& o) { return siemens_output(compensate_siemens(m, o)); }},
      {"isg", "Beckhoff/ISG TF5280 volumetric compensation: ISO 230-1 parameters in the ISG CSV format",
       [](const Machine& m, const CompensationOptions& o) { return isg_output(compensate_isg(m, o)); }},
      {"etalon", "Beckhoff/ISG TF5280: the same parameters in the Etalon exchange format (vendor variant)",
       [](const Machine& m, const CompensationOptions& o) { return etalon_output(compensate_etalon(m, o)); }},
      {"heidenhain", "HEIDENHAIN TNC: nonlinear axis-error tables *.COM (axis = F(axis), sag) and their config.cma",
       [](const Machine& m, const CompensationOptions& o) { return heidenhain_output(compensate_heidenhain(m, o)); }},
      {"fanuc", "FANUC: pitch error compensation parameters 3620-3625 and values per point (sign to check)",
       [](const Machine& m, const CompensationOptions& o) { return fanuc_output(compensate_fanuc(m, o)); }},
      {"klipper", "Klipper: skew profile (xy_skew, xz_skew, yz_skew) and SET_SKEW from the squareness errors",
       [](const Machine& m, const CompensationOptions& o) { return klipper_output(compensate_skew(m, o, "klipper")); }},
      {"marlin", "Marlin: M852 I J K skew factors and Configuration.h defines from the squareness errors",
       [](const Machine& m, const CompensationOptions& o) { return marlin_output(compensate_skew(m, o, "marlin")); }},
      {"rrf", "RepRapFirmware: M556 S X Y Z axis skew compensation from the squareness errors",
       [](const Machine& m, const CompensationOptions& o) { return rrf_output(compensate_skew(m, o, "rrf")); }},
      {"fluidnc", "FluidNC: Skewed kinematics section (needs a build with pull request #849) from the squareness",
       [](const Machine& m, const CompensationOptions& o) { return fluidnc_output(compensate_skew(m, o, "fluidnc")); }},
  };
  return targets;
}

const CompensationTarget& compensation_target(const std::string& name) {
  std::string known;
  for (const auto& t : compensation_targets()) {
    if (t.name == name) return t;
    known += (known.empty() ? "" : ", ") + t.name;
  }
  throw InputError({"", 0, "format"},
                   "unknown compensation target '" + printable(name) + "' (expected one of: " + known + ")");
}

namespace {

// Removes a temporary directory on every way out unless released.
struct TemporaryDirectory {
  fs::path path;
  bool keep = false;
  ~TemporaryDirectory() {
    std::error_code ec;
    if (!keep && !path.empty()) fs::remove_all(path, ec);
  }
};

}  // namespace

void write_target_output(const std::string& dir, const TargetOutput& output) {
  fs::path target = fs::path(dir).lexically_normal();
  if (target.filename().empty()) target = target.parent_path();  // "comp/" names the directory comp
  if (target.empty()) throw Error("output directory '" + printable(dir) + "': expected a directory name");
  std::error_code ec;
  if (fs::exists(target, ec)) {
    if (!fs::is_directory(target, ec) || !fs::is_empty(target, ec))
      throw Error("output directory " + dir + " exists and is not empty: expected a new or empty directory");
  }
  for (const auto& f : output.files)
    if (f.name.empty() || f.name.find('/') != std::string::npos || f.name == "." || f.name == "..")
      throw Error("compensation file name '" + printable(f.name) + "' is not a plain file name");
  const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::string pattern = (parent / (target.filename().string() + ".tmp-XXXXXX")).string();
  if (!mkdtemp(pattern.data())) throw Error("cannot create a temporary directory beside " + dir);
  TemporaryDirectory tmp{pattern};
  // mkdtemp creates 0700; the output directory gets what any new directory of the user gets.
  fs::permissions(tmp.path, static_cast<fs::perms>(permissions_from_umask(0777)), ec);
  for (const auto& f : output.files) {
    std::ofstream out(tmp.path / f.name, std::ios::binary);
    out << f.text;
    out.close();
    if (!out) throw Error("cannot write " + (target / f.name).string());
  }
  if (fs::exists(target, ec)) fs::remove(target, ec);  // empty, checked above
  fs::rename(tmp.path, target, ec);
  if (ec) throw Error("cannot rename " + tmp.path.string() + " to " + dir + ": " + ec.message());
  tmp.keep = true;
}

}  // namespace mtcal
