// libFuzzer target: the ISO 230-2 laser-interferometer .dat file (Renishaw-style key = value blocks).
#include "fuzz_common.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mtcal::fuzz::write_input(data, size, ".dat");
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_positioning_dat(path); });
  return 0;
}
