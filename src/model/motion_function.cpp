#include "mtcal/model/motion_function.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace mtcal {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
// Clang 14 lacks class template argument deduction for aggregates (P1816): spell the guide out.
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

// Interpolation weights of a clamped linear table: value = w0 * v[i0] + w1 * v[i0 + 1].
struct Bracket {
  std::size_t i0;
  double w0, w1;
};

Bracket bracket(const std::vector<double>& x, double q) {
  assert(x.size() >= 2);
  // NaN compares false with every position: upper_bound would return end() and x[i1] be read past
  // the table (found by AddressSanitizer). A NaN position gives a NaN value, reported downstream.
  if (std::isnan(q)) return {0, q, q};
  if (q <= x.front()) return {0, 1.0, 0.0};
  if (q >= x.back()) return {x.size() - 2, 0.0, 1.0};
  auto it = std::upper_bound(x.begin(), x.end(), q);
  std::size_t i1 = static_cast<std::size_t>(it - x.begin());
  std::size_t i0 = i1 - 1;
  double t = (q - x[i0]) / (x[i1] - x[i0]);
  return {i0, 1.0 - t, t};
}

// Weights of the forward and backward table for a direction of motion.
std::pair<double, double> direction_weights(const Table& t, int dir) {
  if (t.backward.empty()) return {1.0, 0.0};
  if (dir > 0) return {1.0, 0.0};
  if (dir < 0) return {0.0, 1.0};
  return {0.5, 0.5};
}

}  // namespace

double MotionFunction::value(double q, int dir) const {
  return std::visit(Overloaded{
                        [&](const Polynomial& p) {
                          const auto& c = p.coefficients;
                          return ((c[3] * q + c[2]) * q + c[1]) * q + c[0] + p.reversal * dir;
                        },
                        [&](const Table& t) {
                          Bracket b = bracket(t.positions, q);
                          auto [wf, wb] = direction_weights(t, dir);
                          double v = wf * (b.w0 * t.forward[b.i0] + b.w1 * t.forward[b.i0 + 1]);
                          if (wb != 0.0) v += wb * (b.w0 * t.backward[b.i0] + b.w1 * t.backward[b.i0 + 1]);
                          return v;
                        },
                        [&](const Fourier& f) {
                          double v = f.constant + f.reversal * dir;
                          for (std::size_t k = 0; k < f.cos_terms.size(); ++k)
                            v += f.cos_terms[k] * std::cos(static_cast<double>(k + 1) * q);
                          for (std::size_t k = 0; k < f.sin_terms.size(); ++k)
                            v += f.sin_terms[k] * std::sin(static_cast<double>(k + 1) * q);
                          return v;
                        },
                    },
                    form_);
}

std::size_t MotionFunction::parameter_count() const {
  return std::visit(Overloaded{
                        [](const Polynomial&) -> std::size_t { return 5; },
                        [](const Table& t) { return t.forward.size() + t.backward.size(); },
                        [](const Fourier& f) { return 2 + f.cos_terms.size() + f.sin_terms.size(); },
                    },
                    form_);
}

std::string MotionFunction::parameter_suffix(std::size_t i) const {
  return std::visit(Overloaded{
                        [&](const Polynomial&) { return i < 4 ? std::to_string(i) : std::string("b"); },
                        [&](const Table& t) {
                          return i < t.forward.size() ? "f" + std::to_string(i)
                                                      : "b" + std::to_string(i - t.forward.size());
                        },
                        [&](const Fourier& f) {
                          if (i == 0) return std::string("c0");
                          if (i <= f.cos_terms.size()) return "c" + std::to_string(i);
                          if (i <= f.cos_terms.size() + f.sin_terms.size())
                            return "s" + std::to_string(i - f.cos_terms.size());
                          return std::string("b");
                        },
                    },
                    form_);
}

int MotionFunction::argument_power(std::size_t i) const {
  if (std::holds_alternative<Polynomial>(form_) && i < 4) return static_cast<int>(i);
  return 0;
}

namespace {
// Reference to parameter i inside a form; the order matches parameter_suffix.
template <class Form>
auto& parameter_ref(Form& form, std::size_t i) {
  using T = std::conditional_t<std::is_const_v<Form>, const double, double>;
  return *std::visit(
      Overloaded{
          [&](auto& p) -> T* {
            using P = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<P, Polynomial>) {
              return i < 4 ? &p.coefficients[i] : &p.reversal;
            } else if constexpr (std::is_same_v<P, Table>) {
              return i < p.forward.size() ? &p.forward[i] : &p.backward[i - p.forward.size()];
            } else {
              if (i == 0) return &p.constant;
              if (i <= p.cos_terms.size()) return &p.cos_terms[i - 1];
              if (i <= p.cos_terms.size() + p.sin_terms.size()) return &p.sin_terms[i - 1 - p.cos_terms.size()];
              return &p.reversal;
            }
          },
      },
      form);
}
}  // namespace

double MotionFunction::parameter(std::size_t i) const {
  assert(i < parameter_count());
  return parameter_ref(form_, i);
}

void MotionFunction::set_parameter(std::size_t i, double v) {
  assert(i < parameter_count());
  parameter_ref(form_, i) = v;
}

void MotionFunction::basis(double q, int dir, std::span<double> out) const {
  assert(out.size() == parameter_count());
  std::visit(Overloaded{
                 [&](const Polynomial&) {
                   out[0] = 1.0;
                   out[1] = q;
                   out[2] = q * q;
                   out[3] = q * q * q;
                   out[4] = static_cast<double>(dir);
                 },
                 [&](const Table& t) {
                   std::fill(out.begin(), out.end(), 0.0);
                   Bracket b = bracket(t.positions, q);
                   auto [wf, wb] = direction_weights(t, dir);
                   out[b.i0] += wf * b.w0;
                   out[b.i0 + 1] += wf * b.w1;
                   if (!t.backward.empty()) {
                     const std::size_t o = t.forward.size();
                     out[o + b.i0] += wb * b.w0;
                     out[o + b.i0 + 1] += wb * b.w1;
                   }
                 },
                 [&](const Fourier& f) {
                   std::size_t i = 0;
                   out[i++] = 1.0;
                   for (std::size_t k = 0; k < f.cos_terms.size(); ++k)
                     out[i++] = std::cos(static_cast<double>(k + 1) * q);
                   for (std::size_t k = 0; k < f.sin_terms.size(); ++k)
                     out[i++] = std::sin(static_cast<double>(k + 1) * q);
                   out[i] = static_cast<double>(dir);
                 },
             },
             form_);
}

bool MotionFunction::is_zero() const {
  for (std::size_t i = 0; i < parameter_count(); ++i)
    if (parameter(i) != 0.0) return false;
  return true;
}

}  // namespace mtcal
