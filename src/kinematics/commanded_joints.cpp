#include "mtcal/kinematics/commanded_joints.hpp"

#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "chain.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

Vec3 unit(int axis) {
  Vec3 v = Vec3::Zero();
  v[axis] = 1.0;
  return v;
}

double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

}  // namespace

// Nominal chain (src/kinematics/chain.cpp, build_chain without errors):
// T = Trans(-w) prod_k [Trans(c_k) J_k(q_k) Trans(-c_k)] Trans(s) Trans(-l a).
struct CommandedJointSolver::Nominal {
  Affine pose;
  Vec3 direction;                              // T.R a: the spindle axis, from the tool point up
  Eigen::Matrix<double, 3, Eigen::Dynamic> dp;  // d point / d q, every joint
  Eigen::Matrix<double, 3, Eigen::Dynamic> da;  // d direction / d q (zero for linear joints)
};

std::optional<std::string> CommandedJointSolver::unsupported(const Machine& m) {
  std::size_t linear = 0, rotary = 0;
  for (const auto& ax : m.axes) (ax.kind == AxisKind::Linear ? linear : rotary) += 1;
  if (linear != 3)
    return fmt::format("topology {} has {} linear axes: the tool point needs exactly three (X, Y, Z) to be placed",
                       m.topology.chain, linear);
  if (rotary > 2)
    return fmt::format(
        "topology {} has {} rotary axes: the tool direction has two degrees of freedom and LinuxCNC's "
        "tool-centre-point world coordinates hold two rotary coordinates; a third one would be redundant",
        m.topology.chain, rotary);
  Mat3 A;
  int col = 0;
  for (const auto& ax : m.axes)
    if (ax.kind == AxisKind::Linear) A.col(col++) = ax.direction();
  if (std::abs(A.determinant()) < 0.5)
    return fmt::format("the linear axes of topology {} are not along three different machine directions",
                       m.topology.chain);
  return std::nullopt;
}

CommandedJointSolver::CommandedJointSolver(const Machine& machine, CommandedJointOptions options)
    : model_(machine), options_(options) {
  if (auto why = unsupported(machine)) throw ModelError(*why);
  if (options.max_iterations < 1 || options.max_iterations > 100)
    throw ModelError(fmt::format("expected an iteration cap from 1 to 100, found {}", options.max_iterations));
  if (!(options.orientation_damping >= 0.0) || !std::isfinite(options.orientation_damping))
    throw ModelError(fmt::format("expected an orientation damping >= 0 rad, found {}", options.orientation_damping));
  for (std::size_t k = 0; k < machine.axes.size(); ++k)
    (machine.axes[k].kind == AxisKind::Linear ? linear_ : rotary_).push_back(k);
}

CommandedJointSolver::Nominal CommandedJointSolver::nominal_at(std::span<const double> q, double tool_length) const {
  const Machine& m = model_.machine();
  const std::size_t n = m.axes.size();
  Nominal out;
  out.dp.setZero(3, static_cast<Eigen::Index>(n));
  out.da.setZero(3, static_cast<Eigen::Index>(n));
  Affine P = Affine::translation(-m.workpiece.origin);
  std::vector<Vec3> omega(n), centre(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = m.axes[k];
    const Vec3 c = ax.kind == AxisKind::Rotary ? ax.point : Vec3::Zero();
    P = P * Affine::translation(c);
    omega[k] = P.R * ax.direction();
    centre[k] = P.t;
    if (ax.kind == AxisKind::Linear) {
      P = P * Affine::translation(ax.direction() * q[k]);
    } else {
      P = P * Affine{axis_rotation(ax.direction_axis, ax.direction_sign * q[k]), Vec3::Zero()};
    }
    P = P * Affine::translation(-c);
  }
  const Vec3 a = unit(m.tool.tool_axis);
  P = P * Affine::translation(m.tool.spindle_point - tool_length * a);
  out.pose = P;
  out.direction = P.R * a;
  for (std::size_t k = 0; k < n; ++k) {
    const auto col = static_cast<Eigen::Index>(k);
    if (m.axes[k].kind == AxisKind::Linear) {
      out.dp.col(col) = omega[k];
    } else {
      out.dp.col(col) = omega[k].cross(P.t - centre[k]);
      out.da.col(col) = omega[k].cross(out.direction);
    }
  }
  return out;
}

Affine CommandedJointSolver::nominal_pose(std::span<const double> q, double tool_length) const {
  if (q.size() != model_.axis_count())
    throw ModelError(fmt::format("expected {} joint values, found {}", model_.axis_count(), q.size()));
  return nominal_at(q, tool_length).pose;
}

Affine CommandedJointSolver::actual_pose(std::span<const double> q, double tool_length) const {
  // The model ends in Trans(-l a) with the machine file's length l: the tool point moves along
  // the actual spindle axis by the difference (exact).
  Affine T = model_.actual_pose(q);
  const Vec3 a = unit(model_.machine().tool.tool_axis);
  T.t += (model_.machine().tool.length - tool_length) * (T.R * a);
  return T;
}

Vec3 CommandedJointSolver::nominal_direction(std::span<const double> q_template, std::span<const double> rotary) const {
  std::vector<double> q(q_template.begin(), q_template.end());
  for (std::size_t j = 0; j < rotary_.size(); ++j) q[rotary_[j]] = rotary[j];
  return nominal_at(q, 0.0).direction;
}

std::vector<double> CommandedJointSolver::nominal_inverse(const CommandedPose& pose, double tool_length) const {
  if (pose.rotary.size() != rotary_.size())
    throw ModelError(fmt::format("expected {} rotary coordinates for topology {}, found {}", rotary_.size(),
                                 model_.machine().topology.chain, pose.rotary.size()));
  std::vector<double> q(model_.axis_count(), 0.0);
  for (std::size_t j = 0; j < rotary_.size(); ++j) q[rotary_[j]] = pose.rotary[j];
  const Nominal n0 = nominal_at(q, tool_length);
  Mat3 A;
  for (int i = 0; i < 3; ++i) A.col(i) = n0.dp.col(static_cast<Eigen::Index>(linear_[static_cast<std::size_t>(i)]));
  const Vec3 dq = A.partialPivLu().solve(pose.point - n0.pose.t);
  for (int i = 0; i < 3; ++i) q[linear_[static_cast<std::size_t>(i)]] = dq[i];
  return q;
}

CommandedPose CommandedJointSolver::nominal_forward(std::span<const double> q, double tool_length) const {
  CommandedPose out;
  out.point = nominal_pose(q, tool_length).t;
  for (std::size_t k : rotary_) out.rotary.push_back(q[k]);
  return out;
}

CommandedJointResult CommandedJointSolver::inverse(const CommandedPose& pose, double tool_length) const {
  CommandedJointResult r;
  r.q = nominal_inverse(pose, tool_length);
  const std::size_t nr = rotary_.size();
  const double lambda2 = options_.orientation_damping * options_.orientation_damping;
  const Vec3 a_target = nominal_direction(r.q, pose.rotary);
  const Vec3 axis = unit(model_.machine().tool.tool_axis);
  Eigen::VectorXd G(static_cast<Eigen::Index>(nr));
  for (int it = 0;; ++it) {
    const Affine T = actual_pose(r.q, tool_length);
    const Vec3 a_actual = T.R * axis;
    const Nominal nom = nominal_at(r.q, tool_length);
    const Vec3 rp = pose.point - T.t;
    // Orientation equation: J^T (a_actual - a_target) + damping^2 (q_rot - rotary) = 0, J the
    // nominal d direction / d q_rot at the joints (first-order condition of the damped least squares).
    Eigen::MatrixXd J(3, static_cast<Eigen::Index>(nr));
    for (std::size_t j = 0; j < nr; ++j) {
      const auto c = static_cast<Eigen::Index>(j);
      J.col(c) = nom.da.col(static_cast<Eigen::Index>(rotary_[j]));
      G[c] = J.col(c).dot(a_actual - a_target) + lambda2 * (r.q[rotary_[j]] - pose.rotary[j]);
    }
    r.iterations = it;
    r.point_residual = rp.norm();
    r.orientation_residual = nr ? G.cwiseAbs().maxCoeff() : 0.0;
    r.direction_error = angle_between(a_actual, a_target);
    if (!std::isfinite(r.point_residual) || !std::isfinite(r.orientation_residual)) return r;
    if (r.point_residual <= options_.point_tolerance && r.orientation_residual <= options_.orientation_tolerance) {
      r.converged = true;
      return r;
    }
    if (it == options_.max_iterations) return r;
    // Quasi-Newton step with the nominal Jacobian: the rotary joints from the orientation
    // equation, then the linear joints for the tool point given the rotary step.
    Eigen::VectorXd drot = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nr));
    if (nr) {
      Eigen::MatrixXd H = J.transpose() * J;
      H.diagonal().array() += lambda2;
      drot = -H.ldlt().solve(G);
    }
    Vec3 rhs = rp;
    for (std::size_t j = 0; j < nr; ++j)
      rhs -= nom.dp.col(static_cast<Eigen::Index>(rotary_[j])) * drot[static_cast<Eigen::Index>(j)];
    Mat3 A;
    for (int i = 0; i < 3; ++i) A.col(i) = nom.dp.col(static_cast<Eigen::Index>(linear_[static_cast<std::size_t>(i)]));
    const Vec3 dlin = A.partialPivLu().solve(rhs);
    for (int i = 0; i < 3; ++i) r.q[linear_[static_cast<std::size_t>(i)]] += dlin[i];
    for (std::size_t j = 0; j < nr; ++j) r.q[rotary_[j]] += drot[static_cast<Eigen::Index>(j)];
  }
}

CommandedJointSolver::ForwardResult CommandedJointSolver::forward(std::span<const double> q, double tool_length) const {
  if (q.size() != model_.axis_count())
    throw ModelError(fmt::format("expected {} joint values, found {}", model_.axis_count(), q.size()));
  ForwardResult out;
  const Affine T = actual_pose(q, tool_length);
  out.pose.point = T.t;
  const std::size_t nr = rotary_.size();
  if (nr == 0) {
    out.converged = std::isfinite(T.t.squaredNorm());
    return out;
  }
  // The rotary coordinates solve inverse()'s orientation equation at these joints:
  // J(q)^T (a_actual(q) - a_nominal(rot)) + damping^2 (q_rot - rot) = 0, Newton in rot.
  const double lambda2 = options_.orientation_damping * options_.orientation_damping;
  const Vec3 a_actual = T.R * unit(model_.machine().tool.tool_axis);
  const Nominal nom = nominal_at(q, tool_length);
  Eigen::MatrixXd J(3, static_cast<Eigen::Index>(nr));
  for (std::size_t j = 0; j < nr; ++j) J.col(static_cast<Eigen::Index>(j)) = nom.da.col(static_cast<Eigen::Index>(rotary_[j]));
  std::vector<double> rot(nr), qt(q.begin(), q.end());
  for (std::size_t j = 0; j < nr; ++j) rot[j] = q[rotary_[j]];
  Eigen::VectorXd G(static_cast<Eigen::Index>(nr));
  for (int it = 0;; ++it) {
    for (std::size_t j = 0; j < nr; ++j) qt[rotary_[j]] = rot[j];
    const Nominal at = nominal_at(qt, tool_length);
    for (std::size_t j = 0; j < nr; ++j)
      G[static_cast<Eigen::Index>(j)] = J.col(static_cast<Eigen::Index>(j)).dot(a_actual - at.direction) +
                                        lambda2 * (q[rotary_[j]] - rot[j]);
    out.iterations = it;
    out.orientation_residual = G.cwiseAbs().maxCoeff();
    if (!std::isfinite(out.orientation_residual)) break;
    if (out.orientation_residual <= options_.orientation_tolerance) {
      out.converged = std::isfinite(T.t.squaredNorm());
      break;
    }
    if (it == options_.max_iterations) break;
    Eigen::MatrixXd Jt(3, static_cast<Eigen::Index>(nr));
    for (std::size_t j = 0; j < nr; ++j) Jt.col(static_cast<Eigen::Index>(j)) = at.da.col(static_cast<Eigen::Index>(rotary_[j]));
    Eigen::MatrixXd H = J.transpose() * Jt;  // -dG/drot
    H.diagonal().array() += lambda2;
    const Eigen::VectorXd step = H.partialPivLu().solve(G);
    for (std::size_t j = 0; j < nr; ++j) rot[j] += step[static_cast<Eigen::Index>(j)];
  }
  out.pose.rotary = rot;
  return out;
}

std::vector<ChainStep> actual_chain_steps(const Machine& m) {
  const auto chain = detail::build_chain(m, true);
  // The last factor is Trans(-l a): the tool length is the module's argument.
  const std::vector<double> q(m.axes.size(), 0.0);
  std::vector<ChainStep> out;
  auto constant = [&](const Affine& v) {
    if (!out.empty() && out.back().kind == ChainStep::Kind::Constant) {
      out.back().value = out.back().value * v;
    } else {
      out.push_back({ChainStep::Kind::Constant, v, -1, 0.0});
    }
  };
  for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
    const auto& f = chain[i];
    if (f.kind == detail::Factor::Kind::Const) {
      constant(f.value);
    } else if (f.kind == detail::Factor::Kind::Joint) {
      out.push_back({ChainStep::Kind::Joint, Affine{}, f.axis,
                     detail::zero_position(m.axes[static_cast<std::size_t>(f.axis)])});
    } else if (f.slot != detail::tool_slot(m.axes.size()) && f.slot != detail::workpiece_slot() && f.slot % 2 == 0) {
      out.push_back({ChainStep::Kind::Motion, Affine{}, (f.slot - 2) / 2, 0.0});
    } else {
      const Affine e = error_transform(detail::slot_errors(m, f.slot, q, {}));
      constant(f.inverse ? e.inverse() : e);
    }
  }
  return out;
}

}  // namespace mtcal
