#include "mtcal/evaluation/diagonals.hpp"
