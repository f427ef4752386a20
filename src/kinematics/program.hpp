// Private: the machine compiled for the batched kernel (constant factors merged).
#pragma once

#include <array>
#include <vector>

#include "chain.hpp"
#include "lane_forms.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

struct ErrorModel::Program {
  struct Op {
    enum class Kind { Const, Joint, Motion };
    Kind kind = Kind::Const;
    Affine value;   // Const
    int axis = -1;  // Joint, Motion
  };
  struct AxisInfo {
    bool rotary = false;
    int coord = 0;                                // machine axis of the nominal direction
    double sign = 1.0;                            // direction sign
    double zero = 0.0;                            // zero position error (internal units)
    double cos_zero = 1.0, sin_zero = 0.0;        // of sign * zero, rotary axes
    std::array<detail::LaneForm, 6> forms{};      // the six motion errors, compiled for the lanes
    // The largest multiple of the position a sine or cosine is taken of: 1 for a rotary joint, the
    // highest Fourier harmonic (0: none). |q| * this beyond kSincosLaneLimit takes the C library.
    double sincos_scale = 0.0;
  };

  std::vector<detail::Factor> chain, nominal_chain;
  std::vector<Op> actual_ops, nominal_ops;
  std::vector<AxisInfo> axes;

  // Grid structure: when each program's ops name the axes in chain order (constants before the
  // first axis, then the ops of axis 0, of axis 1 ...), the pose is S * F_0(q_0) * ... * F_n-1(q_n-1)
  // with one factor per axis, so that a grid needs each factor once per grid value.
  // segment[k] = first op of axis k's factor; segment[n] = ops.size().
  bool grid_structured = false;
  std::vector<std::size_t> actual_segment, nominal_segment;

  explicit Program(const Machine& m);
};

}  // namespace mtcal
