#include "mtcal/io/gcode.hpp"
