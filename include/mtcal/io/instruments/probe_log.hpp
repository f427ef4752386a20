// Probe logs read back (docs/planning.md): LinuxCNC's PROBEOPEN log and the ISO #5061 CSV, as logged contacts.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mtcal/identification/planning.hpp"

namespace mtcal {

enum class ProbeLogFormat {
  // LinuxCNC: one line per G38 probe, nine blank-separated numbers X Y Z A B C U V W (mm, deg),
  // as (PROBEOPEN file) writes them.
  LinuxCNC,
  // ISO: one line per G31, "#5061,#5062,#5063[,#5064,#5065,#5066]" (X Y Z [A B C], mm, deg),
  // comma- or blank-separated; a first line of column names (#5061,... or X,Y,Z,...) and '#'
  // comments after a blank are allowed, empty lines skipped.
  IsoCsv,
};

// The contacts in order, axis values in chain order (internal units: mm, rad; NaN for an axis of
// the machine the log does not carry). Throws InputError with file and line for a line that is
// not numbers, a wrong count of numbers, non-finite values. An empty log gives no contact (not an
// error here: measurements_from_contacts names the first contact missing).
std::vector<LoggedContact> parse_probe_log(const Machine& m, std::string_view text, const std::string& source,
                                           ProbeLogFormat format);
std::vector<LoggedContact> read_probe_log(const Machine& m, const std::string& path, ProbeLogFormat format);

// Contacts a program in tool-point coordinates logged (ProbeCoordinates::ToolPoint, run on a
// tool-centre-point kinematics: the log holds the world position X Y Z of the tool point and the
// rotary coordinates) as the axis values of the machine's nominal chain (ToolPointCoordinates::axes).
// On a compensating kinematics the world position is that module's forward — its model's actual tool
// point — so the axis values are those whose nominal tool point is there. Throws InputError with file
// and line for a contact without a value the conversion needs.
std::vector<LoggedContact> contacts_from_tool_points(const Machine& m, std::vector<LoggedContact> contacts);

}  // namespace mtcal
