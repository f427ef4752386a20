// libFuzzer target: the G-code reader (toolpath, compensate --gcode, predict --gcode) in its ISO dialect, under a
// setup with work offsets, a tool table and G28/G30 positions so that G54-G59.3, G43 H and G28 paths run too.
#include "fuzz_common.hpp"
#include "mtcal/io/gcode/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mtcal::GcodeSetup setup = [] {
    mtcal::GcodeSetup s;
    s.work_offsets[1] = {100, 50, -200, 0, 0, 0};
    s.work_offsets[8] = {-1, 2, -3, 10, 0, 0};
    s.g28 = {0, 0, 0, 0, 0, 0};
    s.g30 = {-10, 20, -5, 0, 0, 0};
    s.tools = mtcal::parse_tool_table("T1 P1 Z50 D6\nT2 P2 Z-10.5 D3\nT7 P7 X1 Z100\n", "fuzz.tbl");
    s.has_tool_table = true;
    return s;
  }();
  mtcal::GcodeOptions options;
  options.setup = setup;
  mtcal::fuzz::expect_mtcal_errors_only(
      [&] { (void)mtcal::parse_gcode(mtcal::fuzz::as_text(data, size), "fuzz.nc", options); });
  return 0;
}
