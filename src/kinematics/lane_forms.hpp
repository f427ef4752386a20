// Internal: motion-error forms (polynomial, Fourier, table) and sine/cosine evaluated for 8 lanes
// at once, written as loops over lanes without calls or branches so that every kernel path
// (baseline, AVX2, AVX-512: util/kernel.hpp) vectorises them.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mtcal/model/motion_function.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::detail {

constexpr int kLanes = 8;
using Lane = double[kLanes];

// Put before a loop over the kLanes lanes of a kernel. GCC vectorises these loops on its own
// (-O3); clang 14's cost model declines them (-Rpass-missed=loop-vectorize on batch.cpp: "the
// cost-model indicates that vectorization is not beneficial", and its full unroll of the 8
// iterations leaves scalar code), which made the clang kernels 2-3x slower than GCC's (bench/,
// docs/building.md). assume_safety also says that the lane arrays of one loop do not overlap,
// which holds for every loop it marks: they are distinct rows of a Block, Lane or table. A
// marked loop that clang cannot vectorise is a warning (-Wpass-failed), an error under
// MTCAL_WERROR, so a loop that calls the C library's sine (Libm) must not carry it.
#if defined(__clang__)
#define MTCAL_VECTORIZE_LOOP _Pragma("clang loop vectorize(assume_safety)")
#else
#define MTCAL_VECTORIZE_LOOP
#endif

// sin and cos to about 1 ulp, written in double arithmetic and selects only, without branches,
// calls or integer work, so that loops over lanes vectorise: Cody-Waite reduction by pi/2 and
// the fdlibm kernel polynomials on [-pi/4, pi/4] (fdlibm k_sin.c, k_cos.c).
[[gnu::always_inline]] inline void sincos_lane(double x, double& s_out, double& c_out) {
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kShift = 6755399441055744.0;  // 1.5 * 2^52: x + kShift - kShift rounds x
  constexpr double kPio2_1 = 1.57079632673412561417e+00;
  constexpr double kPio2_2 = 6.07710050630396597660e-11;
  constexpr double kPio2_3 = 2.02226624871116645580e-21;
  const double k = (x * kTwoOverPi + kShift) - kShift;
  const double r = ((x - k * kPio2_1) - k * kPio2_2) - k * kPio2_3;
  const double z = r * r;
  const double sp = r + r * z *
                            (-1.66666666666666324348e-01 +
                             z * (8.33333333332248946124e-03 +
                                  z * (-1.98412698298579493134e-04 +
                                       z * (2.75573137070700676789e-06 +
                                            z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
  const double cp = 1.0 - 0.5 * z +
                    z * z *
                        (4.16666666666666019037e-02 +
                         z * (-1.38888888888741095749e-03 +
                              z * (2.48015872894767294178e-05 +
                                   z * (-2.75573143513906633035e-07 +
                                        z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
  // Quadrant m = k mod 4 in {-2, -1, 0, 1, 2} (-2 and 2 are the same quadrant).
  const double m = k - 4.0 * ((k * 0.25 + kShift) - kShift);
  // Equality tests only, combined with `|`: they cannot trap, so the compiler evaluates them all
  // and turns the selects into vector blends on every level (an ordered comparison behind `||`
  // stays a branch unless the code is built without trapping math).
  const bool odd = (m == 1.0) | (m == -1.0);
  const double s1 = odd ? cp : sp;
  const double c1 = odd ? sp : cp;
  s_out = ((m == -1.0) | (m == -2.0) | (m == 2.0)) ? -s1 : s1;  // quadrants 2 and 3
  c_out = ((m == 1.0) | (m == -2.0) | (m == 2.0)) ? -c1 : c1;   // quadrants 1 and 2
}

// Below 2^22 rad (about 4e6) sincos_lane's three-part reduction by pi/2 stays within 2 ulp of the
// C library (measured); beyond, it loses digits (1e-3 relative at 1e16 rad). A block of
// configurations with a larger argument (continuous rotary axes turned a million times, high
// harmonics of such angles) is run with std::sin and std::cos instead (the kernels' `Libm`
// instantiation, chosen per block before the hot code: the same choice on every kernel level).
constexpr double kSincosLaneLimit = 4194304.0;  // 2^22

// sin and cos of one lane, the kernel's own or the C library's.
template <bool Libm>
[[gnu::always_inline]] inline void sincos_of(double x, double& s, double& c) {
  if constexpr (Libm) {
    s = std::sin(x);
    c = std::cos(x);
  } else {
    sincos_lane(x, s, c);
  }
}

// for (l) sincos_of<Libm>(x(l), s[l], c[l]) over the lanes, marked for clang only where it can
// vectorise (the kernel's own sine, not the C library's).
template <bool Libm, class X>
[[gnu::always_inline]] inline void sincos_lanes(X x, Lane& s, Lane& c) {
  if constexpr (Libm) {
    for (int l = 0; l < kLanes; ++l) sincos_of<true>(x(l), s[l], c[l]);
  } else {
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) sincos_lane(x(l), s[l], c[l]);
  }
}

// One motion-error function compiled for the lanes: its form's numbers in flat arrays.
struct LaneForm {
  enum class Kind { Polynomial, Fourier, Table };
  Kind kind = Kind::Polynomial;
  double poly[5] = {0, 0, 0, 0, 0};  // c0 c1 c2 c3 reversal (polynomial)
  double constant = 0.0, reversal = 0.0;  // Fourier
  std::vector<double> cos_terms, sin_terms;  // Fourier a_1.., b_1..
  std::vector<double> positions, forward, backward;  // table; backward empty: forward both ways
  std::int64_t first_step = 0;  // table: largest power of two <= positions.size() - 2

  LaneForm() = default;
  explicit LaneForm(const MotionFunction& f) {
    if (const auto* p = std::get_if<Polynomial>(&f.form())) {
      kind = Kind::Polynomial;
      for (int i = 0; i < 4; ++i) poly[i] = p->coefficients[static_cast<std::size_t>(i)];
      poly[4] = p->reversal;
    } else if (const auto* s = std::get_if<Fourier>(&f.form())) {
      kind = Kind::Fourier;
      constant = s->constant;
      reversal = s->reversal;
      cos_terms = s->cos_terms;
      sin_terms = s->sin_terms;
    } else {
      const auto& t = std::get<Table>(f.form());
      kind = Kind::Table;
      if (t.positions.size() < 2 || t.forward.size() != t.positions.size() ||
          (!t.backward.empty() && t.backward.size() != t.positions.size()))
        throw ModelError("motion-error table: expected at least 2 positions and as many values per run, found " +
                         std::to_string(t.positions.size()) + " positions, " + std::to_string(t.forward.size()) +
                         " forward and " + std::to_string(t.backward.size()) + " backward values");
      positions = t.positions;
      forward = t.forward;
      backward = t.backward;
      const auto last = static_cast<std::uint64_t>(positions.size() - 2);
      first_step = last ? static_cast<std::int64_t>(std::bit_floor(last)) : 0;
    }
  }

  // The highest harmonic of a Fourier series (0 for the other forms).
  std::size_t harmonics() const { return std::max(cos_terms.size(), sin_terms.size()); }
};

// out = f(q, dir) for 8 lanes. Polynomials and tables give the same bits as MotionFunction::value
// (the same operations in the same order); a Fourier series differs from it by a few ulp of its
// terms (sincos_lane against the C library's sine and cosine, within 2 ulp below kSincosLaneLimit,
// and the sines' sum); Libm takes the C library's.
template <bool Libm = false>
[[gnu::always_inline]] inline void motion_lanes(const LaneForm& f, const Lane& q, const Lane& dir, Lane& out) {
  switch (f.kind) {
    case LaneForm::Kind::Polynomial: {
      const double* p = f.poly;
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) out[l] = ((p[3] * q[l] + p[2]) * q[l] + p[1]) * q[l] + p[0] + p[4] * dir[l];
      return;
    }
    case LaneForm::Kind::Fourier: {
      // The constant and reversal, then the cosine terms in MotionFunction::value's order; the sine
      // terms are summed beside them and added last (value adds them one by one after the
      // cosines: a difference of a few ulp of the terms, as the sine and cosine's own). Every
      // harmonic takes both its sine and cosine (0 where a list is shorter): with one of them
      // unused the compiler would move each polynomial under its quadrant's branch, and no
      // longer vectorise.
      const std::size_t nc = f.cos_terms.size(), ns = f.sin_terms.size(), n = f.harmonics();
      // The sines start at -0, which adds to anything exactly: with no sine term the sum below
      // leaves value's bits, a -0 included.
      double sines[kLanes];
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) {
        out[l] = f.constant + f.reversal * dir[l];
        sines[l] = -0.0;
      }
      for (std::size_t k = 0; k < n; ++k) {
        const double a = k < nc ? f.cos_terms[k] : 0.0, b = k < ns ? f.sin_terms[k] : 0.0;
        const double h = static_cast<double>(k + 1);
        double s[kLanes], c[kLanes];
        sincos_lanes<Libm>([&](int l) { return h * q[l]; }, s, c);
        MTCAL_VECTORIZE_LOOP
        for (int l = 0; l < kLanes; ++l) {
          out[l] += a * c[l];
          sines[l] += b * s[l];
        }
      }
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) out[l] += sines[l];
      return;
    }
    case LaneForm::Kind::Table: {
      // Clamped linear interpolation as MotionFunction::value's bracket. q is first clamped to the
      // table (a NaN passes both clamps and gives NaN weights, as there). i0 is the largest index
      // in [0, n - 2] with x[i0] <= q, found by a branch-free binary search (one step per bit of
      // n - 2, the same steps in every lane).
      const double* x = f.positions.data();
      const std::int64_t last = static_cast<std::int64_t>(f.positions.size()) - 2;
      const double lo = x[0], hi = x[last + 1];
      double qc[kLanes];
      std::int64_t i0[kLanes];
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) {
        qc[l] = q[l] < lo ? lo : (q[l] > hi ? hi : q[l]);
        i0[l] = 0;
      }
      for (std::int64_t step = f.first_step; step > 0; step >>= 1)
        MTCAL_VECTORIZE_LOOP
        for (int l = 0; l < kLanes; ++l) {
          const std::int64_t j = std::min(i0[l] + step, last);
          i0[l] = x[j] <= qc[l] ? j : i0[l];
        }
      double w0[kLanes], w1[kLanes], x0[kLanes], x1[kLanes];
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) {
        x0[l] = x[i0[l]];
        x1[l] = x[i0[l] + 1];
      }
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) {
        // The bracket's exact end weights (also where the last interval's width overflows, and
        // for -0 at a first position 0); t itself between the ends.
        const double t = (qc[l] - x0[l]) / (x1[l] - x0[l]);
        w1[l] = qc[l] <= lo ? 0.0 : (qc[l] >= hi ? 1.0 : t);
        w0[l] = 1.0 - w1[l];
      }
      const double* fw = f.forward.data();
      if (f.backward.empty()) {
        // MotionFunction's 1.0 * (...) is exact.
        MTCAL_VECTORIZE_LOOP
        for (int l = 0; l < kLanes; ++l) out[l] = w0[l] * fw[i0[l]] + w1[l] * fw[i0[l] + 1];
        return;
      }
      const double* bw = f.backward.data();
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) {
        // The direction weights of MotionFunction::value: + forward, - backward, 0 their mean.
        const double wf = dir[l] > 0.0 ? 1.0 : (dir[l] < 0.0 ? 0.0 : 0.5);
        const double wb = dir[l] > 0.0 ? 0.0 : (dir[l] < 0.0 ? 1.0 : 0.5);
        const double v = wf * (w0[l] * fw[i0[l]] + w1[l] * fw[i0[l] + 1]);
        const double b = wb * (w0[l] * bw[i0[l]] + w1[l] * bw[i0[l] + 1]);
        out[l] = wb != 0.0 ? v + b : v;
      }
      return;
    }
  }
}

}  // namespace mtcal::detail
