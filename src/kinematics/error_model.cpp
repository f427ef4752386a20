#include "mtcal/kinematics/error_model.hpp"

#include <cassert>

#include "chain.hpp"
#include "program.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

using detail::Factor;

namespace {

void check_sizes(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir) {
  if (q.size() != m.axes.size())
    throw ModelError("expected " + std::to_string(m.axes.size()) + " joint values for topology " + m.topology.chain +
                     ", found " + std::to_string(q.size()));
  if (!dir.empty() && dir.size() != m.axes.size())
    throw ModelError("expected " + std::to_string(m.axes.size()) + " directions of motion, found " +
                     std::to_string(dir.size()));
}

Vec3 vee(const Mat3& A) {
  return Vec3(0.5 * (A(2, 1) - A(1, 2)), 0.5 * (A(0, 2) - A(2, 0)), 0.5 * (A(1, 0) - A(0, 1)));
}

}  // namespace

VolumetricError volumetric_error(const Affine& actual, const Affine& nominal) {
  // dR = Ra Rn^T summed in a fixed order, so that equal rotations give an exactly symmetric
  // product and an exactly zero rotation vector (as the batched kernel does).
  Mat3 dR;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      dR(i, j) = actual.R(i, 0) * nominal.R(j, 0) + actual.R(i, 1) * nominal.R(j, 1) + actual.R(i, 2) * nominal.R(j, 2);
  return {actual.t - nominal.t, rotation_vector(dR)};
}

Affine ErrorModel::actual_pose(std::span<const double> q, std::span<const std::int8_t> dir) const {
  check_sizes(machine_, q, dir);
  std::vector<Affine> v(program_->chain.size());
  detail::bind_chain(machine_, program_->chain, true, q, dir, v);
  return detail::multiply(v);
}

Affine ErrorModel::nominal_pose(std::span<const double> q) const {
  check_sizes(machine_, q, {});
  std::vector<Affine> v(program_->nominal_chain.size());
  detail::bind_chain(machine_, program_->nominal_chain, false, q, {}, v);
  return detail::multiply(v);
}

VolumetricError ErrorModel::evaluate(std::span<const double> q, std::span<const std::int8_t> dir) const {
  return volumetric_error(actual_pose(q, dir), nominal_pose(q));
}

void ErrorModel::slot_jacobian(std::span<const double> q, std::span<const std::int8_t> dir,
                               JacobianWorkspace& ws) const {
  // d(output)/d(each of the six values of every error slot), through the exact chain:
  // for T = P F S, dT = P dF S (and -P' dE S' for a factor that is an inverse E^-1).
  const Machine& m = machine_;
  const std::size_t n = m.axes.size();
  const auto& chain = program_->chain;
  const std::size_t nf = chain.size();
  ws.values.resize(nf);
  ws.prefix.resize(nf + 1);
  ws.suffix.resize(nf + 1);
  detail::bind_chain(m, chain, true, q, dir, ws.values);
  // prefix[i] = F_0 ... F_{i-1}; suffix[i] = F_i ... F_last.
  ws.prefix[0] = Affine{};
  for (std::size_t i = 0; i < nf; ++i) ws.prefix[i + 1] = ws.prefix[i] * ws.values[i];
  ws.suffix[nf] = Affine{};
  for (std::size_t i = nf; i-- > 0;) ws.suffix[i] = ws.values[i] * ws.suffix[i + 1];

  const Affine& T = ws.prefix[nf];
  ws.nominal.resize(program_->nominal_chain.size());
  detail::bind_chain(m, program_->nominal_chain, false, q, {}, ws.nominal);
  const Affine T0 = detail::multiply(ws.nominal);
  const Vec3 r = rotation_vector(T.R * T0.R.transpose());
  const Mat3 Jinv = left_jacobian_inverse(r);
  const Mat3 RtT = T.R.transpose();

  auto& G = ws.slot_jacobian;
  G.setZero(6, 6 * detail::slot_count(n));
  // Adds sign * d(output) for dT = P [D|v] S into column col of G.
  auto add = [&](int col, const Affine& P, const AffineDerivative& d, const Affine& S, double sign) {
    const Vec3 dt = P.R * (d.D * S.t + d.v);
    const Mat3 dR = P.R * d.D * S.R;
    G.col(col).head<3>() += sign * dt;
    G.col(col).tail<3>() += sign * (Jinv * vee(dR * RtT));
  };

  for (std::size_t i = 0; i < nf; ++i) {
    const Factor& fa = chain[i];
    if (fa.kind == Factor::Kind::Joint) {
      const Axis& ax = m.axes[fa.axis];
      const int col = 6 * detail::location_slot(fa.axis) + detail::zero_position_component(ax);
      // The joint runs at q + sign * E_0 (zero position E_0 in the machine axis's sense).
      add(col, ws.prefix[i], detail::joint_motion_derivative(ax, q[fa.axis] + detail::zero_position(ax)),
          ws.suffix[i + 1], ax.direction_sign);
      continue;
    }
    if (fa.kind != Factor::Kind::Slot) continue;
    const Error6 e = detail::slot_errors(m, fa.slot, q, dir);
    for (int c = 0; c < 6; ++c) {
      // A location slot's zero position acts through the joint (handled above).
      if (fa.slot % 2 == 1 && c == detail::zero_position_component(m.axes[static_cast<std::size_t>((fa.slot - 1) / 2)]))
        continue;
      const auto d = error_transform_derivative(e, c);
      const int col = 6 * fa.slot + c;
      if (!fa.inverse) {
        add(col, ws.prefix[i], d, ws.suffix[i + 1], 1.0);
      } else {
        // d(E^-1) = -E^-1 dE E^-1: dT = -P_{i+1} dE (F_i S_{i+1}).
        add(col, ws.prefix[i + 1], d, ws.suffix[i], -1.0);
      }
    }
  }
}

void ErrorModel::jacobian(std::span<const double> q, std::span<const std::int8_t> dir,
                          Eigen::Ref<Eigen::Matrix<double, 6, Eigen::Dynamic>> J, JacobianWorkspace& ws) const {
  check_sizes(machine_, q, dir);
  const Machine& m = machine_;
  const std::size_t n = m.axes.size();
  if (static_cast<std::size_t>(J.cols()) != m.parameter_count())
    throw ModelError("Jacobian needs " + std::to_string(m.parameter_count()) + " columns, found " +
                     std::to_string(J.cols()));
  slot_jacobian(q, dir, ws);
  const auto& G = ws.slot_jacobian;
  // Parameters: each is linear in its slot component (value = sum p_i basis_i).
  std::size_t col = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = m.axes[k];
    const int d = dir.empty() ? 0 : dir[k];
    for (int c = 0; c < 6; ++c) {
      const auto& fn = ax.motion[c];
      ws.basis.resize(fn.parameter_count());
      fn.basis(q[k], d, ws.basis);
      for (double b : ws.basis) J.col(static_cast<Eigen::Index>(col++)) = G.col(6 * detail::motion_slot(k) + c) * b;
    }
    for (int c = 0; c < 6; ++c)
      if (ax.allows_location(static_cast<Component>(c)))
        J.col(static_cast<Eigen::Index>(col++)) = G.col(6 * detail::location_slot(k) + c);
  }
  for (int s : {detail::tool_slot(n), detail::workpiece_slot()})
    for (int c = 0; c < 6; ++c) J.col(static_cast<Eigen::Index>(col++)) = G.col(6 * s + c);
  assert(col == m.parameter_count());
}

std::vector<ErrorSensitivity> ErrorModel::error_sensitivities(std::span<const double> q,
                                                              std::span<const std::int8_t> dir) const {
  check_sizes(machine_, q, dir);
  JacobianWorkspace ws;
  slot_jacobian(q, dir, ws);
  const auto& G = ws.slot_jacobian;
  const std::size_t n = machine_.axes.size();
  std::vector<ErrorSensitivity> out;
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = machine_.axes[k];
    for (int c = 0; c < 6; ++c)
      out.push_back({{ErrorKind::Motion, static_cast<Component>(c), ax.letter}, G.col(6 * detail::motion_slot(k) + c)});
    for (int c = 0; c < 6; ++c)
      if (ax.allows_location(static_cast<Component>(c)))
        out.push_back(
            {{ErrorKind::Location, static_cast<Component>(c), ax.letter}, G.col(6 * detail::location_slot(k) + c)});
  }
  for (char body : {'t', 'w'}) {
    const int s = body == 't' ? detail::tool_slot(n) : detail::workpiece_slot();
    for (int c = 0; c < 6; ++c)
      out.push_back({{ErrorKind::Mounting, static_cast<Component>(c), body}, G.col(6 * s + c)});
  }
  return out;
}

Eigen::Matrix<double, 6, Eigen::Dynamic> ErrorModel::jacobian(std::span<const double> q,
                                                              std::span<const std::int8_t> dir) const {
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, static_cast<Eigen::Index>(machine_.parameter_count()));
  JacobianWorkspace ws;
  jacobian(q, dir, J, ws);
  return J;
}

}  // namespace mtcal
