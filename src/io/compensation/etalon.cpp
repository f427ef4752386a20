#include "mtcal/io/compensation/etalon.hpp"

#include <fmt/format.h>

namespace mtcal {

std::string etalon_text(const IsgCompensation& c) {
  std::string text =
      "// Written by mtcal compensate --format etalon: Etalon exchange format, vendor variant, as the ISG/Beckhoff\n"
      "// TF5280 volumetric compensation reads it. Numbers are errors (e = actual - nominal) of the machine model:\n"
      "// position errors in mm or rad, component errors in mm or rad at arguments in mm or deg.\n";
  for (const auto& [name, value] : c.position_errors) text += fmt::format("[{}]\nVALUE = {}\n", name, value);
  for (const auto& t : c.tables)
    for (std::size_t k = 0; k < t.names.size(); ++k) {
      text += fmt::format("[{}]\nGridpoints = {{\n", t.names[k]);
      for (std::size_t i = 0; i < t.position.size(); ++i)
        text += fmt::format("  {} {}\n", t.position[i], t.values[k][i]);
      text += fmt::format("}}  // end of {}\n", t.names[k]);
    }
  return text;
}

TargetOutput etalon_output(const IsgCompensation& c) {
  TargetOutput out;
  out.summary = c.summary;
  out.files.push_back({"volcomp.etalon", etalon_text(c)});
  out.files.push_back(
      {"README.txt",
       "volcomp.etalon: the machine model's ISO 230-1/-7 errors in the Etalon exchange format (vendor variant),\n"
       "written by mtcal compensate --format etalon.\n"
       "\n"
       "Loading (Beckhoff TF5280 / ISG kernel volumetric compensation):\n"
       "  1. copy volcomp.etalon to the control;\n"
       "  2. the start-up list (hochlauf.lis) names the list file of compensation i,\n"
       "       vol_comp[0].file_name  C:\\volcomp\\vol_comp_0.lis   (P-STUP-00101)\n"
       "     and vol_comp[0].max_records (P-STUP-00100) bounds the number of parameter blocks;\n"
       "  3. that list file declares the parameter file and its format: its keys are not in the documentation\n"
       "     mtcal's authors could read, so it is not written here - take them from the TF5280 manual.\n"
       "\n"
       "Numbers: errors e = actual - nominal (not corrections), mm or rad; arguments mm or deg.\n"
       "Position errors are named without the leading E ([C0B]), component errors with it ([EXY]), as in the\n"
       "manual's example. The control corrects the tool position, not its orientation.\n"
       "mtcal reads this file back as a parameter file: mtcal ... --params volcomp.etalon\n"});
  return out;
}

}  // namespace mtcal
