// The prediction-model YAML file (docs/prediction.md): read into the domain's PredictionModel.
#pragma once

#include <string>

#include "mtcal/prediction/prediction_model.hpp"

namespace mtcal {

// Reads the YAML model file (format in docs/prediction.md). InputError with file, line and the
// dotted key for every problem: unknown key or model form, missing parameter, stages not
// increasing, an 'of' naming no earlier component ...
PredictionModel read_prediction_model(const std::string& path);
PredictionModel parse_prediction_model(const std::string& text, const std::string& source);

}  // namespace mtcal
