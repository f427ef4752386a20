// libFuzzer target: the method-comparison CSV (mtcal compare).
#include "fuzz_common.hpp"
#include "mtcal/io/instruments/iso230_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(mtcal::fuzz::as_text(data, size));
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_comparison_csv(text, "fuzz.csv"); });
  return 0;
}
