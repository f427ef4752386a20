// libFuzzer target: the Renishaw LaserXL/CARTO ASCII export (.rtl linear, .rta rotary; io/laser_files).
#include "fuzz_common.hpp"
#include "mtcal/io/instruments/laser_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The first byte's low bit picks the linear or the rotary reading of the same text.
  const bool rotary = size > 0 && (data[0] & 1) != 0;
  const std::string text(mtcal::fuzz::as_text(data, size));
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_laser_file(text, "fuzz.rtl", rotary); });
  return 0;
}
