// Motion-error functions of an axis position: polynomial with reversal term, tables, Fourier series.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace mtcal {

// Mohammed 2019 eq. 3-1: E(q) = E0 + E1 q + E2 q^2 + E3 q^3 + Eb * sign(direction of motion).
// Coefficients in internal units: (mm or rad) / (mm or rad)^i.
struct Polynomial {
  std::array<double, 4> coefficients{};
  double reversal = 0.0;
};

// Values at increasing positions, linearly interpolated, held constant beyond the ends.
// forward is used when moving in +, backward when moving in -; an empty backward table means
// the forward one serves both directions. With no direction given, the mean of the two is used.
struct Table {
  std::vector<double> positions;  // internal units (mm or rad), strictly increasing, >= 2
  std::vector<double> forward;
  std::vector<double> backward;
};

// E(q) = c0 + sum_k (a_k cos kq + b_k sin kq) + Eb * sign(direction); for rotary axes (q in rad).
struct Fourier {
  double constant = 0.0;
  std::vector<double> cos_terms;  // a_1 ... a_n
  std::vector<double> sin_terms;  // b_1 ... b_n
  double reversal = 0.0;
};

// A motion error as a function of its axis's position q and direction of motion dir (-1, 0, +1).
// Every form is linear in its parameters: value = sum_i parameter_i * basis_i(q, dir), which is
// what makes the sensitivity Jacobian exact.
class MotionFunction {
 public:
  using Form = std::variant<Polynomial, Table, Fourier>;

  MotionFunction() = default;
  explicit MotionFunction(Form form) : form_(std::move(form)) {}

  const Form& form() const { return form_; }
  Form& form() { return form_; }

  double value(double q, int dir) const;

  std::size_t parameter_count() const;
  // Suffix naming parameter i after the error name: "0".."3" and "b" (polynomial),
  // "f<i>" / "b<i>" (table forward / backward), "c0", "c<k>", "s<k>", "b" (Fourier).
  std::string parameter_suffix(std::size_t i) const;
  // Power of the argument unit in parameter i's unit (polynomial coefficient i -> i, else 0).
  int argument_power(std::size_t i) const;
  double parameter(std::size_t i) const;
  void set_parameter(std::size_t i, double v);
  // d value / d parameter_i at (q, dir) for every parameter; out.size() == parameter_count().
  void basis(double q, int dir, std::span<double> out) const;

  bool is_zero() const;

 private:
  Form form_;
};

}  // namespace mtcal
