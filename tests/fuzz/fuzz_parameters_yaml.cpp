// libFuzzer target: the parameter file reader (YAML) applied to an example 5-axis machine.
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mtcal::Machine m = mtcal::fuzz::example_machine("hu40t-wCBXfYZt.yaml");
  mtcal::fuzz::expect_mtcal_errors_only(
      [&] { mtcal::apply_parameters(m, mtcal::fuzz::as_text(data, size), "fuzz-params.yaml"); });
  return 0;
}
