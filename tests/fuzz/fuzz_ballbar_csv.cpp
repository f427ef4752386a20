// libFuzzer target: the ballbar trace CSV.
#include "fuzz_common.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mtcal::fuzz::write_input(data, size, ".csv");
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_ballbar_csv(path); });
  return 0;
}
