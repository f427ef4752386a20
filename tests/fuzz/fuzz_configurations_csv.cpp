// libFuzzer target: the configurations CSV (mtcal eval --points) on a 5-axis machine.
#include "fuzz_common.hpp"
#include "mtcal/io/points/error_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto& m = mtcal::fuzz::example_machine("hu40t-wCBXfYZt.yaml");
  const std::string path = mtcal::fuzz::write_input(data, size, ".csv");
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_configurations(m, path, true); });
  return 0;
}
