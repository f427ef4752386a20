// libFuzzer target: the prediction model file (YAML, mtcal predict --model).
#include "fuzz_common.hpp"
#include "mtcal/io/model/prediction_model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(mtcal::fuzz::as_text(data, size));
  mtcal::fuzz::expect_mtcal_errors_only([&] { (void)mtcal::parse_prediction_model(text, "fuzz-model.yaml"); });
  return 0;
}
