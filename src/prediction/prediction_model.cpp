#include "mtcal/prediction/prediction_model.hpp"
