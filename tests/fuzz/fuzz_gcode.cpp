// libFuzzer target: the G-code reader (toolpath, compensate --gcode, predict --gcode).
#include "fuzz_common.hpp"
#include "mtcal/io/gcode.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_gcode(mtcal::fuzz::as_text(data, size), "fuzz.nc"); });
  return 0;
}
