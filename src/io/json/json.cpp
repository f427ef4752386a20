#include "mtcal/io/json/json.hpp"

#include <string>

#include "mtcal/model/joints.hpp"

namespace mtcal {

Json joint_json(const Machine& m, std::span<const double> q) {
  Json j = Json::object();
  for (std::size_t k = 0; k < m.axes.size(); ++k) j[std::string(1, m.axes[k].letter)] = to_user_units(m.axes[k], q[k]);
  return j;
}

}  // namespace mtcal
