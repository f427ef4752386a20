#include "jacobian_check.hpp"

#include <cmath>

namespace mtcal::testing {

Eigen::Matrix<double, 6, Eigen::Dynamic> numeric_jacobian(const Machine& m, std::span<const double> q,
                                                          std::span<const std::int8_t> dir) {
  const auto params = m.parameters();
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, static_cast<Eigen::Index>(params.size()));
  for (std::size_t i = 0; i < params.size(); ++i) {
    // The error is a difference of tool positions hundreds of mm from the origin, rounded to
    // about 1e-13 mm: each step changes the error by about 1e-4 mm or 1e-6 rad at this
    // configuration, large against rounding yet small enough for the model's curvature.
    const bool rot = is_rotation(params[i].error.component);
    const auto& unit = params[i].unit;
    int power = 0;
    if (unit.find('/') != std::string::npos) {
      const auto caret = unit.find('^');
      power = caret == std::string::npos ? 1 : unit[caret + 1] - '0';
    }
    double arg = 1.0;
    if (auto k = m.axis_index(params[i].error.body)) arg = std::max(1e-2, std::abs(q[*k]));
    const double h = (rot ? 1e-6 : 1e-4) / std::pow(arg, power);
    Machine plus = m, minus = m;
    plus.set_parameter(i, params[i].value + h);
    minus.set_parameter(i, params[i].value - h);
    const auto ep = ErrorModel(plus).evaluate(q, dir);
    const auto em = ErrorModel(minus).evaluate(q, dir);
    Eigen::Matrix<double, 6, 1> d;
    d << ep.translation - em.translation, ep.rotation - em.rotation;
    J.col(static_cast<Eigen::Index>(i)) = d / (2 * h);
  }
  return J;
}

}  // namespace mtcal::testing
