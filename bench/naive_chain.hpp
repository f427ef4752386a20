// Naive reference implementation of the volumetric error, for the benchmark baseline: the chain
// that src/kinematics/chain.cpp (build_chain) documents, built per configuration as a
// std::vector of 4x4 homogeneous matrices and multiplied in order. Written independently of
// src/kinematics: only the public machine model (and MotionFunction::value) is used.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal::bench {

// Factors of T_w->t, workpiece to tool, at one configuration:
//   actual:  E_w^-1 W^-1 prod_k [Trans(c) L M(q+z) L^-1 Trans(-c) Trans(r) E_k Trans(-r)] S E_t Trans(-l a)
//   nominal: W^-1 prod_k [Trans(c) M(q) Trans(-c) Trans(r) Trans(-r)] S Trans(-l a)
// (c: rotary axis point, 0 for linear axes; r: axis point; z: zero-position error; L: location
// error without zero position; E_k: motion errors at q_k; E = Trans(d) Rz(c) Ry(b) Rx(a)).
std::vector<Eigen::Matrix4d> naive_chain(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir,
                                         bool errors);

// Product of the factors in order.
Eigen::Matrix4d naive_product(const std::vector<Eigen::Matrix4d>& factors);

// Actual minus nominal tool point and rotation vector of R_actual R_nominal^T.
VolumetricError naive_evaluate(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir);

}  // namespace mtcal::bench
