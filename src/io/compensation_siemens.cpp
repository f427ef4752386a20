#include "mtcal/io/compensation_siemens.hpp"

#include <fmt/format.h>

namespace mtcal {

TargetOutput siemens_output(const SiemensCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  std::string text = "%_N_AX_EEC_INI\n";
  text +=
      "; Written by mtcal compensate --format siemens: encoder/leadscrew error compensation, values are errors in mm\n"
      "; (a positive value moves the axis negative). Load as a part program, then NCK reset; MD32700 "
      "ENC_COMP_ENABLE.\n";
  text += "CHANDATA(1)\n";
  for (const auto& t : c.tables) {
    const std::string ax = fmt::format("AX{}", t.machine_axis);
    text += fmt::format("; axis {} = {}\n", t.axis, ax);
    for (std::size_t i = 0; i < t.values.size(); ++i)
      text += fmt::format("$AA_ENC_COMP[0,{},{}]={:.9f}\n", i, ax, t.values[i]);
    text += fmt::format("$AA_ENC_COMP_STEP[0,{}]={:.6f}\n", ax, t.step);
    text += fmt::format("$AA_ENC_COMP_MIN[0,{}]={:.6f}\n", ax, t.min);
    text += fmt::format("$AA_ENC_COMP_MAX[0,{}]={:.6f}\n", ax, t.max);
    text += fmt::format("$AA_ENC_COMP_IS_MODULO[0,{}]=0\n", ax);
  }
  text += "M17\n";
  out.files.push_back({"AX_EEC.INI", std::move(text)});
  return out;
}

}  // namespace mtcal
