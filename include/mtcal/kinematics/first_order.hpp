// Classic first-order sum model of a 3-axis machine (Fletcher 2009 fig. 2 style): a cross-check.
#pragma once

#include <cstdint>
#include <span>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// Tool-point and orientation error of a machine with linear axes only, as the first-order sum
// of each error's effect (small-angle, rigid-body; Fletcher 2009 section 3, Yaqoob 2017 eq. 2.1):
//   e = -d_w - eps_w x p + sum_k [ z_k e_k + q_k (o_k x u_k) + d_k + eps_k x (p_k - r_k) ]
//       + d_t - l eps_t x a
// with p the nominal tool point in the workpiece frame, p_k the tool point in the frame carried
// by axis k, r_k the axis's reference point, o_k its orientation errors, z_k its zero position
// along the machine axis e_k, u_k = +-e_k its commanded direction. Agrees with ErrorModel to second order in the error
// size. Throws ModelError for a machine with a rotary axis.
VolumetricError first_order_error(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir = {});

}  // namespace mtcal
