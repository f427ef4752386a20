// libFuzzer target: the two CSV tokenisers every table reader starts from (numeric and text cells).
#include "fuzz_common.hpp"
#include "mtcal/io/text/csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(mtcal::fuzz::as_text(data, size));
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_csv(text, "fuzz.csv"); });
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_text_csv(text, "fuzz.csv"); });
  return 0;
}
