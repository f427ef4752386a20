#include "mtcal/evaluation/toolpath.hpp"
