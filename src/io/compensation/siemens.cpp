#include "mtcal/io/compensation/siemens.hpp"

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
  if (c.cec.empty()) return out;
  std::string cec = "%_N_NC_CEC_INI\n";
  cec +=
      "; Written by mtcal compensate --format siemens: sag/angularity (cross-axis) compensation, values are\n"
      "; corrections in mm added to the compensation (output) axis as a function of the base (input) axis:\n"
      "; straightness, sag and squareness. Load with MD32710 CEC_ENABLE = 0, then enable MD32710 on the output\n"
      "; axes and $SN_CEC_TABLE_ENABLE[t] per table; MD18342 MM_CEC_MAX_POINTS[t] >= the points (840D sl).\n";
  cec += "CHANDATA(1)\n";
  for (std::size_t t = 0; t < c.cec.size(); ++t) {
    const SiemensCecTable& k = c.cec[t];
    cec += fmt::format("; table {}: {} (AX{}) as a function of {} (AX{})\n", t, k.output, k.output_machine_axis,
                       k.input, k.input_machine_axis);
    for (std::size_t i = 0; i < k.values.size(); ++i) cec += fmt::format("$AN_CEC[{},{}]={:.9f}\n", t, i, k.values[i]);
    cec += fmt::format("$AN_CEC_INPUT_AXIS[{}]=(AX{})\n", t, k.input_machine_axis);
    cec += fmt::format("$AN_CEC_OUTPUT_AXIS[{}]=(AX{})\n", t, k.output_machine_axis);
    cec += fmt::format("$AN_CEC_STEP[{}]={:.6f}\n", t, k.step);
    cec += fmt::format("$AN_CEC_MIN[{}]={:.6f}\n", t, k.min);
    cec += fmt::format("$AN_CEC_MAX[{}]={:.6f}\n", t, k.max);
    cec += fmt::format("$AN_CEC_DIRECTION[{}]=0\n", t);
    cec += fmt::format("$AN_CEC_MULT_BY_TABLE[{}]=0\n", t);
    cec += fmt::format("$AN_CEC_IS_MODULO[{}]=0\n", t);
  }
  cec += "M17\n";
  out.files.push_back({"NC_CEC.INI", std::move(cec)});
  return out;
}

}  // namespace mtcal
