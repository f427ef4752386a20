#include "mtcal/io/compensation/fanuc.hpp"

#include <fmt/format.h>

namespace mtcal {

TargetOutput fanuc_output(const FanucCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  std::string text =
      "; FANUC pitch error compensation, written by mtcal compensate --format fanuc.\n"
      "; THE VALUES ARE CORRECTIONS (c = -e, what the control adds to the axis). NO PUBLIC FANUC DOCUMENT\n"
      "; CONFIRMS THIS SIGN: CHECK IT ON THE CONTROL BEFORE USE (one point with a large value, then measure).\n"
      "; Point n holds the increment over the section ending at its compensation position,\n"
      "; position(n) = (n - 3620) x 3624 from the reference position, in counts of detection unit x 3623.\n";
  std::string axes;
  for (const auto& a : c.axes) axes += fmt::format(" {}={}", a.axis_number, a.axis);
  text += fmt::format("; axis columns (controlled axis number = name):{}\n", axes);
  auto row = [&](int no, const char* what, auto value) {
    std::string line = fmt::format("PARAMETER {:04d}", no);
    for (const auto& a : c.axes) line += fmt::format(" {:>12}", value(a));
    text += line + fmt::format("  ; {}\n", what);
  };
  row(3620, "number of the compensation point of the reference position",
      [](const FanucPitchAxis& a) { return fmt::format("{}", a.reference_number); });
  row(3621, "number of the farthest compensation point on the - side",
      [](const FanucPitchAxis& a) { return fmt::format("{}", a.min_number); });
  row(3622, "number of the farthest compensation point on the + side",
      [](const FanucPitchAxis& a) { return fmt::format("{}", a.max_number); });
  row(3623, "magnification", [](const FanucPitchAxis& a) { return fmt::format("{}", a.magnification); });
  row(3624, "interval of the compensation points (mm or deg)",
      [](const FanucPitchAxis& a) { return fmt::format("{:.4f}", a.interval); });
  row(3625, "travel per revolution of a rotary axis (deg; 0: not a rotary table)",
      [](const FanucPitchAxis& a) { return fmt::format("{:.4f}", a.travel_per_rev); });
  for (const auto& a : c.axes) {
    const char* unit = a.rotary ? "deg" : "mm";
    text += fmt::format("; axis {} ({}): points {} to {}, reference position at point {}, one count = {:g} {} x {}\n",
                        a.axis, a.axis_number, a.min_number, a.max_number, a.reference_number, a.detection_unit, unit,
                        a.magnification);
    for (std::size_t i = 0; i < a.values.size(); ++i) {
      const int n = a.min_number + static_cast<int>(i);
      const double to = static_cast<double>(n - a.reference_number) * a.interval;
      std::string where = fmt::format("{} {:.4f} .. {:.4f} {}", a.axis, to - a.interval, to, unit);
      if (a.travel_per_rev > 0 && n == a.reference_number)
        where = fmt::format("{} same as point {}", a.axis, a.max_number);
      text += fmt::format("PITCH {:04d} {:+5d}  ; {}\n", n, a.values[i], where);
    }
  }
  out.files.push_back({"fanuc-pitch.txt", std::move(text)});
  out.files.push_back(
      {"README.txt",
       "fanuc-pitch.txt: FANUC pitch error compensation written by mtcal compensate --format fanuc.\n"
       "\n"
       "Entering it (MDI, parameter write enabled): key in the PARAMETER lines as parameters 3620-3625 of each\n"
       "axis (one column per controlled axis, named at the top of the file), then the PITCH lines on the pitch\n"
       "error compensation screen (point number, value). Turn the power off and on, then return to the\n"
       "reference position: the compensation is counted from there.\n"
       "\n"
       "Numbers: values are CORRECTIONS (c = -e) in counts of the detection unit x magnification (3623), each\n"
       "the increment over the section ending at its point. The sign is an assumption that no public FANUC\n"
       "document confirms: CHECK IT ON THE CONTROL (enter one large value, move across its point, measure).\n"
       "The reference position is taken at axis position 0 of the machine model; if the control's reference\n"
       "position is elsewhere, the numbers must be shifted. Bidirectional compensation (3605#0, 3626, 3627) is\n"
       "not written: the mean of both directions is, and the reversal is listed as not held.\n"
       "A rotary table's values (3625 = 360) sum to zero and its reference point repeats the last value.\n"});
  return out;
}

}  // namespace mtcal
