#include "mtcal/evaluation/contributions.hpp"
