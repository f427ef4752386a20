// libFuzzer target: the Etalon exchange format read as a parameter file (io/etalon_file), applied
// to the 5-axis example machine.
#include "fuzz_common.hpp"
#include "mtcal/io/model/etalon_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = mtcal::fuzz::as_text(data, size);
  mtcal::Machine m = mtcal::fuzz::example_machine("hu40t-wCBXfYZt.yaml");
  mtcal::fuzz::expect_mtcal_errors_only([&] {
    (void)mtcal::looks_like_etalon(text);
    mtcal::apply_etalon(m, text, "fuzz.etalon");
  });
  return 0;
}
