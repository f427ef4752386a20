// libFuzzer target: the machine file reader (YAML).
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mtcal::fuzz::expect_mtcal_errors_only(
      [&] { (void)mtcal::parse_machine(mtcal::fuzz::as_text(data, size), "fuzz.yaml"); });
  return 0;
}
