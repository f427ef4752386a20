// libFuzzer target: the rotary-axis probing files (contacts and sphere centres per indexation).
#include "fuzz_common.hpp"
#include "mtcal/io/instruments/probing_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mtcal::fuzz::write_input(data, size, ".csv");
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_contacts_csv(path, 'C'); });
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_centres_csv(path, 'C'); });
  return 0;
}
