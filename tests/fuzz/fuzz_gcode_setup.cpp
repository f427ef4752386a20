// libFuzzer target: the setup files of a G-code program: a LinuxCNC tool table and parameter file (io/gcode/reader.hpp).
#include "fuzz_common.hpp"
#include "mtcal/io/gcode/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = mtcal::fuzz::as_text(data, size);
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_tool_table(text, "fuzz.tbl", 25.4); });
  mtcal::fuzz::expect_mtcal_errors_only([&] {
    mtcal::GcodeSetup s;
    mtcal::parse_parameter_file(text, "fuzz.var", s, 25.4);
  });
  return 0;
}
