// libFuzzer target: the separation inputs (position observations per step, dimension table).
#include "fuzz_common.hpp"
#include "mtcal/io/text/csv.hpp"
#include "mtcal/io/instruments/separation_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(mtcal::fuzz::as_text(data, size));
  mtcal::fuzz::expect_mtcal_errors_only([&] {
    const auto t = mtcal::parse_text_csv(text, "fuzz.csv");
    mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_position_observations(t, "fuzz.csv"); });
    mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_dimension_table(t, "fuzz.csv"); });
  });
  return 0;
}
