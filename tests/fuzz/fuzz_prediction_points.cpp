// libFuzzer target: the prediction points CSV (mtcal predict --points).
#include "fuzz_common.hpp"
#include "mtcal/io/points/prediction_points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = mtcal::fuzz::write_input(data, size, ".csv");
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::read_prediction_points(path); });
  return 0;
}
