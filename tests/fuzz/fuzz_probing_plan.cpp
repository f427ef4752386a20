// libFuzzer target: the probing plan / measurement CSV (simulate, identify, identifiability) on a
// 5-axis machine.
#include "fuzz_common.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto& m = mtcal::fuzz::example_machine("hu40t-wCBXfYZt.yaml");
  const std::string text(mtcal::fuzz::as_text(data, size));
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_probing_csv(m, text, "fuzz-plan.csv"); });
  return 0;
}
