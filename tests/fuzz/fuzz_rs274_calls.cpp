// libFuzzer target: the reader of LinuxCNC's canonical calls (the output of rs274 -g, io/gcode/rs274.hpp).
#include "fuzz_common.hpp"
#include "mtcal/io/gcode/rs274.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mtcal::fuzz::expect_mtcal_errors_only(
      [&] { (void)mtcal::parse_canon(mtcal::fuzz::as_text(data, size), "fuzz.ngc"); });
  return 0;
}
