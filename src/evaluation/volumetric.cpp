#include "mtcal/evaluation/volumetric.hpp"
