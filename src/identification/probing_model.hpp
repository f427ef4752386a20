// Internal: the measurement equations of a probing plan and their Jacobian over the unknowns.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mtcal/identification/identification.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal::detail {

// Unknowns x = [machine parameters (chosen) | per feature: ball centre (3), facet offset (1),
// ballbar pivot centre in its plane and length offset (3), laser offset (1) | pre-travel].
// Residuals, weighted by 1/sigma:
//   ball record:    p(q, dir) - c_b                       (3; the tool point on the ball centre)
//   facet record:   n . p(q, dir) - d_f + pretravel        (1; the probe centre on the plane)
//   ballbar record: |p(q, dir) - c_s| + delta_s - l        (1; l the bar's reading, ISO 230-4)
//   laser record:   d . p(q, dir) - o_s - l                (1; l the displacement read along the beam d)
//   scale bar:      |c_a - c_b| - L                        (1)
// with p the actual tool point in the workpiece frame (ErrorModel, exact chain).
class ProbingModel {
 public:
  ProbingModel(const Machine& base, const ProbingPlan& plan, std::vector<std::size_t> parameters,
               const std::vector<ScaleBar>& scale_bars, bool pretravel, double sigma_ball, double sigma_facet,
               double sigma_scale_bar, double sigma_ballbar = 1e-3, double sigma_laser = 1e-3);

  std::size_t unknowns() const { return n_; }
  std::size_t residuals() const { return m_; }
  std::size_t blocks() const { return plan_.records.size() + bars_.size(); }  // records, then scale bars
  std::size_t block_size(std::size_t b) const;
  std::vector<std::string> names() const;
  const std::vector<std::size_t>& parameters() const { return params_; }
  std::size_t ball_column(std::size_t feature) const { return col_[feature]; }
  std::size_t facet_column(std::size_t feature) const { return col_[feature]; }
  std::size_t pretravel_column() const { return pre_col_; }
  bool has_pretravel() const { return pretravel_; }

  // Starting values: the base machine's parameters, nominal artefact, no pre-travel.
  Eigen::VectorXd initial() const;
  // Residuals of block b at x; J (block_size x unknowns, row-major) if not null.
  void block(const double* x, std::size_t b, double* r, double* J) const;
  // All residuals, and the dense Jacobian (rows in block order) if not null.
  void evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd* J) const;
  // The machine with x's parameter values.
  Machine machine(const double* x) const;
  ArtefactState artefact(const double* x) const;
  // Feature f's unknowns from an artefact state, into x (its columns; used features only).
  void put_artefact(std::size_t f, const ArtefactState& a, double* x) const;
  bool is_ball_block(std::size_t b) const;
  bool is_facet_block(std::size_t b) const;
  ProbeFeature::Kind block_kind(std::size_t b) const;  // of a record block (a scale bar: not called)
  double sigma(std::size_t b) const;

 private:
  const ErrorModel& model(const double* x) const;

  Machine base_;
  ProbingPlan plan_;
  std::vector<std::size_t> params_;
  struct Bar {
    std::size_t a, b;
    double length;
  };
  std::vector<Bar> bars_;
  bool pretravel_;
  double sb_, sf_, ss_, sbb_, sl_;
  std::size_t n_ = 0, m_ = 0, pre_col_ = 0;
  std::vector<std::size_t> col_;  // per feature: first column of its unknowns
  // The compiled model for the last parameter values (rebuilt when they change).
  mutable std::vector<double> cached_;
  mutable std::unique_ptr<ErrorModel> model_;
  mutable JacobianWorkspace ws_;
  mutable Eigen::Matrix<double, 6, Eigen::Dynamic> full_;
};

// Machine parameter indices for names (parameters or errors, Machine::parameter_index first);
// InputError for an unknown name, duplicates removed, order kept.
std::vector<std::size_t> parameter_indices(const Machine& m, const std::vector<std::string>& names,
                                           const std::string& option);

}  // namespace mtcal::detail
