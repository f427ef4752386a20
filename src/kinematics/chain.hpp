// Private: the factor chain of a machine (workpiece to tool) shared by the scalar, Jacobian and
// batched evaluations, so that all three compute the same product.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mtcal/kinematics/transform.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal::detail {

// One factor of T = F_0 F_1 ... F_m.
struct Factor {
  enum class Kind { Const, Joint, Slot };
  Kind kind = Kind::Const;
  Affine value;          // value of a Const factor
  int slot = -1;         // Slot: error slot index (see slot numbering below)
  bool inverse = false;  // Slot: the factor is the inverse of the slot's error transform
  int axis = -1;         // Joint: axis index
};

// Error slots: 0 workpiece mounting; 1 + 2k location of axis k; 2 + 2k motion of axis k;
// 2 + 2n tool mounting.
inline int workpiece_slot() { return 0; }
inline int location_slot(std::size_t k) { return 1 + 2 * static_cast<int>(k); }
inline int motion_slot(std::size_t k) { return 2 + 2 * static_cast<int>(k); }
inline int tool_slot(std::size_t n) { return 2 + 2 * static_cast<int>(n); }
inline int slot_count(std::size_t n) { return 3 + 2 * static_cast<int>(n); }

// Component of the location slot that is the axis's zero position (applied through the joint).
int zero_position_component(const Axis& ax);
// Zero position in the axis's command sense: added to the commanded position q.
double zero_position(const Axis& ax);
// The location transform of the axis line without the zero position.
Error6 location_without_zero(const Axis& ax);

// Nominal joint motion about/along the axis's coordinate direction through the origin.
Affine joint_motion(const Axis& ax, double s);
// d joint_motion / d s.
AffineDerivative joint_motion_derivative(const Axis& ax, double s);

// Symbolic chain: Const factors hold their values; Slot and Joint factors are placeholders.
// With errors == false the chain is the nominal one (no Slot factors, zero positions 0).
std::vector<Factor> build_chain(const Machine& m, bool errors);

// Values of every factor at one configuration; values.size() == chain.size(). With errors ==
// false (nominal chain) the zero positions are not applied.
void bind_chain(const Machine& m, const std::vector<Factor>& chain, bool errors, std::span<const double> q,
                std::span<const std::int8_t> dir, std::span<Affine> values);

// The six error values of a slot at one configuration (location slots without zero position).
Error6 slot_errors(const Machine& m, int slot, std::span<const double> q, std::span<const std::int8_t> dir);

// Product of the values.
Affine multiply(std::span<const Affine> values);

}  // namespace mtcal::detail
