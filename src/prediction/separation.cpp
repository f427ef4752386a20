#include "mtcal/prediction/separation.hpp"
