// Exact volumetric error of a machine: actual vs nominal tool pose, batched, with its Jacobian.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "mtcal/kinematics/transform.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// Volumetric error at one configuration, in the workpiece frame: actual minus nominal tool
// point (mm) and the rotation vector of R_actual * R_nominal^T (rad). Output order dx dy dz rx ry rz.
struct VolumetricError {
  Vec3 translation = Vec3::Zero();
  Vec3 rotation = Vec3::Zero();
};

struct BatchOptions {
  int threads = 0;  // 0: all hardware threads
};

// Reusable storage of ErrorModel::jacobian: sized once per model, no allocation per call.
// Effect of one error's value on the volumetric error at a configuration:
// d(dx dy dz rx ry rz) / d(error value), whatever form the error's function has. Per unit of
// error: mm/mm and rad/mm for translational errors, mm/rad and rad/rad for rotational ones.
struct ErrorSensitivity {
  ErrorName error;
  Eigen::Matrix<double, 6, 1> effect;
};

class JacobianWorkspace {
 public:
  JacobianWorkspace() = default;

 private:
  friend class ErrorModel;
  std::vector<Affine> values, prefix, suffix, nominal;
  std::vector<double> basis;
  Eigen::Matrix<double, 6, Eigen::Dynamic> slot_jacobian;
};

// The machine compiled for evaluation. Joint values q are in internal units (mm, rad), one per
// axis in the machine's chain order; dir holds the direction of motion per axis (-1, 0, +1;
// empty means 0: no reversal term).
class ErrorModel {
 public:
  explicit ErrorModel(const Machine& machine);
  ~ErrorModel();
  ErrorModel(const ErrorModel&);
  ErrorModel& operator=(const ErrorModel&);
  ErrorModel(ErrorModel&&) noexcept;
  ErrorModel& operator=(ErrorModel&&) noexcept;

  const Machine& machine() const { return machine_; }
  std::size_t axis_count() const { return machine_.axes.size(); }

  VolumetricError evaluate(std::span<const double> q, std::span<const std::int8_t> dir = {}) const;
  // Tool pose in the workpiece frame, with errors (actual) or without (nominal).
  Affine actual_pose(std::span<const double> q, std::span<const std::int8_t> dir = {}) const;
  Affine nominal_pose(std::span<const double> q) const;

  // N configurations: q row-major N x axis_count, dir empty or N x axis_count, out N x 6
  // (dx dy dz rx ry rz). Splits the work over threads; no allocation per configuration.
  void evaluate_batch(std::span<const double> q, std::span<const std::int8_t> dir, std::span<double> out,
                      const BatchOptions& options = {}) const;

  // A stretch of a full grid: values[k] are axis k's sample values (chain order, internal units),
  // configurations in mixed-radix order with the last axis fastest, no directions of motion;
  // out receives out.size() / 6 configurations from index `first` on (dx dy dz rx ry rz each).
  // Where the chain allows (grid_structured()) each axis' actual and nominal transform is computed
  // once per grid value and the poses are products of these, the outer axes' prefix product
  // shared by every value of the last axis: the same numbers as evaluate_batch on the listed
  // configurations to rounding (1e-13 mm, tested to 1e-12 mm), at a fraction of the work.
  void evaluate_grid(std::span<const std::vector<double>> values, std::size_t first, std::span<double> out,
                     const BatchOptions& options = {}) const;
  // Whether evaluate_grid can use the product structure (otherwise it evaluates point by point).
  bool grid_structured() const;
  // Floating-point operations (additions, multiplications, divisions, square roots) per
  // configuration of evaluate_batch and of evaluate_grid's kernel on this machine, counted from
  // the kernels' code (src/kinematics/batch.cpp): the arithmetic side of an efficiency figure
  // (docs/performance.md). Comparisons, selects and loads are not counted.
  double batch_flops_per_configuration() const;
  double grid_flops_per_configuration() const;

  // Sensitivity Jacobian d(dx dy dz rx ry rz) / d(parameter) at one configuration, columns in
  // the order of Machine::parameters(). Exact (analytic through the exact transforms).
  void jacobian(std::span<const double> q, std::span<const std::int8_t> dir,
                Eigen::Ref<Eigen::Matrix<double, 6, Eigen::Dynamic>> J, JacobianWorkspace& ws) const;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(std::span<const double> q,
                                                    std::span<const std::int8_t> dir = {}) const;

  // Sensitivity to every error of the machine (motion errors as values, location errors,
  // mounting errors) in the order of Machine::parameters() (tool mounting before workpiece).
  std::vector<ErrorSensitivity> error_sensitivities(std::span<const double> q,
                                                    std::span<const std::int8_t> dir = {}) const;

  struct Program;  // compiled factor chains of the batched kernel

 private:
  void slot_jacobian(std::span<const double> q, std::span<const std::int8_t> dir, JacobianWorkspace& ws) const;

  Machine machine_;
  std::unique_ptr<Program> program_;
};

// Volumetric error of a pose pair: translation difference and rotation vector of Ra * Rn^T.
VolumetricError volumetric_error(const Affine& actual, const Affine& nominal);

}  // namespace mtcal
