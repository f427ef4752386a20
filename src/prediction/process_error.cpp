#include "mtcal/prediction/process_error.hpp"
