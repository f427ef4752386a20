#include "mtcal/prediction/regression.hpp"
