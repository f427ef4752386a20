// The batched kernel: blocks of configurations in structure-of-arrays form so that every step is
// a loop over lanes the compiler vectorises; the same chain as detail::build_chain.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/interrupt.hpp"
#include "mtcal/util/parallel.hpp"
#include "program.hpp"
#include "../util/kernel.hpp"
#include "mtcal/kinematics/kernel_isa.hpp"

namespace mtcal {

using detail::Factor;
using Op = ErrorModel::Program::Op;

ErrorModel::Program::Program(const Machine& m)
    : chain(detail::build_chain(m, true)), nominal_chain(detail::build_chain(m, false)) {
  auto compile = [&](const std::vector<Factor>& ch, bool errors, std::vector<Op>& ops) {
    Affine acc;
    bool pending = false;
    std::vector<Affine> values(ch.size());
    const std::vector<double> q0(m.axes.size(), 0.0);
    detail::bind_chain(m, ch, errors, q0, {}, values);  // constant slots' values
    auto flush = [&] {
      if (pending) ops.push_back({Op::Kind::Const, acc, -1});
      acc = Affine{};
      pending = false;
    };
    for (std::size_t i = 0; i < ch.size(); ++i) {
      const Factor& f = ch[i];
      const bool motion =
          f.kind == Factor::Kind::Slot && f.slot >= 2 && f.slot % 2 == 0 && f.slot != detail::tool_slot(m.axes.size());
      if (f.kind == Factor::Kind::Joint) {
        flush();
        ops.push_back({Op::Kind::Joint, Affine{}, f.axis});
      } else if (motion) {
        const auto& fns = m.axes[static_cast<std::size_t>((f.slot - 2) / 2)].motion;
        if (std::all_of(fns.begin(), fns.end(), [](const MotionFunction& fn) { return fn.is_zero(); }))
          continue;  // error-free axis: nothing to apply (and exact zeros for a zero machine)
        flush();
        ops.push_back({Op::Kind::Motion, Affine{}, (f.slot - 2) / 2});
      } else if (f.kind == Factor::Kind::Const || values[i].R != Mat3::Identity() || values[i].t != Vec3::Zero()) {
        // Error-free slots are skipped so that a machine without errors runs exactly the nominal
        // program and its error comes out as exact zeros rather than rounding residue.
        acc = acc * values[i];
        pending = true;
      }
    }
    flush();
  };
  compile(chain, true, actual_ops);
  compile(nominal_chain, false, nominal_ops);

  auto segments = [&](const std::vector<Op>& ops, std::vector<std::size_t>& seg) {
    const std::size_t n = m.axes.size();
    seg.assign(n + 1, ops.size());
    int current = -1;
    for (std::size_t i = 0; i < ops.size(); ++i) {
      const int a = ops[i].kind == Op::Kind::Const ? current : ops[i].axis;
      if (a == current) continue;
      if (a != current + 1) return false;  // an axis out of chain order: no product structure
      current = a;
      seg[static_cast<std::size_t>(a)] = i;
    }
    return current == static_cast<int>(n) - 1;
  };
  grid_structured = segments(actual_ops, actual_segment) && segments(nominal_ops, nominal_segment);

  for (const Axis& ax : m.axes) {
    AxisInfo a;
    a.rotary = ax.kind == AxisKind::Rotary;
    a.coord = ax.direction_axis;
    a.sign = ax.direction_sign;
    a.zero = detail::zero_position(ax);
    a.cos_zero = std::cos(a.sign * a.zero);
    a.sin_zero = std::sin(a.sign * a.zero);
    for (std::size_t c = 0; c < 6; ++c) {
      a.forms[c] = detail::LaneForm(ax.motion[c]);
      a.sincos_scale = std::max(a.sincos_scale, static_cast<double>(a.forms[c].harmonics()));
    }
    if (a.rotary) a.sincos_scale = std::max(a.sincos_scale, 1.0);
    axes.push_back(a);
  }
}

namespace {

using detail::kLanes;
using detail::Lane;
using detail::sincos_lane;

// Rigid transforms of kLanes configurations, rotation row-major r[3*i+j].
struct Block {
  Lane r[9];
  Lane t[3];
};

[[gnu::always_inline]] inline void set_identity(Block& b) {
  for (int i = 0; i < 9; ++i)
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) b.r[i][l] = (i % 4 == 0) ? 1.0 : 0.0;
  for (int i = 0; i < 3; ++i)
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) b.t[i][l] = 0.0;
}

// P = P * X, where x(row, col, lane) gives X's rotation (col < 3) and translation (col == 3).
// Row i of the product needs only row i of P, so each row is read into registers and
// overwritten in place.
template <class Get>
[[gnu::always_inline]] inline void mul(Block& P, Get x) {
  for (int i = 0; i < 3; ++i) {
    double* p0 = P.r[3 * i];
    double* p1 = P.r[3 * i + 1];
    double* p2 = P.r[3 * i + 2];
    double* pt = P.t[i];
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      const double a = p0[l], b = p1[l], c = p2[l];
      p0[l] = a * x(0, 0, l) + b * x(1, 0, l) + c * x(2, 0, l);
      p1[l] = a * x(0, 1, l) + b * x(1, 1, l) + c * x(2, 1, l);
      p2[l] = a * x(0, 2, l) + b * x(1, 2, l) + c * x(2, 2, l);
      pt[l] += a * x(0, 3, l) + b * x(1, 3, l) + c * x(2, 3, l);
    }
  }
}

// P = P * C for a constant transform C.
[[gnu::always_inline]] inline void mul_const(Block& P, const Affine& C) {
  mul(P, [&C](int i, int j, int) { return j < 3 ? C.R(i, j) : C.t(i); });
}

// P = P * X for per-lane transforms X.
[[gnu::always_inline]] inline void mul_block(Block& P, const Block& X) {
  mul(P, [&X](int i, int j, int l) { return j < 3 ? X.r[3 * i + j][l] : X.t[i][l]; });
}

// P = P * Rot(axis a, angle) given cos and sin per lane: only two columns change.
[[gnu::always_inline]] inline void mul_rotation(Block& P, int a, const Lane& c, const Lane& s) {
  const int i = (a + 1) % 3, j = (a + 2) % 3;
  for (int row = 0; row < 3; ++row) {
    double* ci = P.r[3 * row + i];
    double* cj = P.r[3 * row + j];
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      const double x = ci[l], y = cj[l];
      ci[l] = x * c[l] + y * s[l];
      cj[l] = -x * s[l] + y * c[l];
    }
  }
}

// P = P * Trans(d * e_a).
[[gnu::always_inline]] inline void mul_translation(Block& P, int a, const Lane& d) {
  for (int row = 0; row < 3; ++row)
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) P.t[row][l] += P.r[3 * row + a][l] * d[l];
}

// Exact error transform Trans(d) Rz(c) Ry(b) Rx(a) per lane (see error_transform).
[[gnu::always_inline]] inline void error_block(Block& E, const Lane (&e)[6]) {
  Lane sa, ca, sb, cb, sc, cc;
  MTCAL_VECTORIZE_LOOP
  for (int l = 0; l < kLanes; ++l) {
    sincos_lane(e[3][l], sa[l], ca[l]);
    sincos_lane(e[4][l], sb[l], cb[l]);
    sincos_lane(e[5][l], sc[l], cc[l]);
  }
  MTCAL_VECTORIZE_LOOP
  for (int l = 0; l < kLanes; ++l) {
    E.r[0][l] = cb[l] * cc[l];
    E.r[1][l] = sa[l] * sb[l] * cc[l] - ca[l] * sc[l];
    E.r[2][l] = ca[l] * sb[l] * cc[l] + sa[l] * sc[l];
    E.r[3][l] = cb[l] * sc[l];
    E.r[4][l] = sa[l] * sb[l] * sc[l] + ca[l] * cc[l];
    E.r[5][l] = ca[l] * sb[l] * sc[l] - sa[l] * cc[l];
    E.r[6][l] = -sb[l];
    E.r[7][l] = sa[l] * cb[l];
    E.r[8][l] = ca[l] * cb[l];
    E.t[0][l] = e[0][l];
    E.t[1][l] = e[1][l];
    E.t[2][l] = e[2][l];
  }
}

struct AxisLanes {
  Lane q, dir;
  Lane nom_c, nom_s, act_c, act_s;  // rotary
  Lane nom_d, act_d;                // linear
};

// Runs a program (actual or nominal) on a block; only the actual one has motion-error ops and
// applies the zero positions. Libm: the C library's sines and cosines (lane_forms.hpp).
template <bool Libm>
[[gnu::always_inline]] inline void run_program(const ErrorModel::Program& prog, const AxisLanes* ax,
                                               const std::vector<Op>& ops, Block& B, bool actual, std::size_t begin = 0,
                                               std::size_t end = static_cast<std::size_t>(-1)) {
  set_identity(B);
  end = std::min(end, ops.size());
  for (std::size_t i = begin; i < end; ++i) {
    const Op& op = ops[i];
    if (op.kind == Op::Kind::Const) {
      mul_const(B, op.value);
      continue;
    }
    const auto& a = prog.axes[op.axis];
    const AxisLanes& L = ax[op.axis];
    if (op.kind == Op::Kind::Joint) {
      if (a.rotary)
        mul_rotation(B, a.coord, actual ? L.act_c : L.nom_c, actual ? L.act_s : L.nom_s);
      else
        mul_translation(B, a.coord, actual ? L.act_d : L.nom_d);
      continue;
    }
    Lane e[6];
    for (std::size_t c = 0; c < 6; ++c) detail::motion_lanes<Libm>(a.forms[c], L.q, L.dir, e[c]);
    Block E;
    error_block(E, e);
    mul_block(B, E);
  }
}

// The joint's sines and cosines (rotary) or displacements (linear) of L.q, nominal and actual.
template <bool Libm>
[[gnu::always_inline]] inline void prepare_axis(const ErrorModel::Program::AxisInfo& a, AxisLanes& L) {
  if (a.rotary) {
    detail::sincos_lanes<Libm>([&](int l) { return a.sign * L.q[l]; }, L.nom_s, L.nom_c);
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      L.act_c[l] = L.nom_c[l] * a.cos_zero - L.nom_s[l] * a.sin_zero;
      L.act_s[l] = L.nom_s[l] * a.cos_zero + L.nom_c[l] * a.sin_zero;
    }
  } else {
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      L.nom_d[l] = a.sign * L.q[l];
      L.act_d[l] = a.sign * (L.q[l] + a.zero);
    }
  }
}

// Output: translation difference and rotation vector of dR = R_actual R_nominal^T.
[[gnu::always_inline]] inline void finish_block(const Block& P, const Block& N, std::size_t count, double* out) {
  Lane res[6], sin_t, cos_t;
  bool small = true;
  MTCAL_VECTORIZE_LOOP
  for (int l = 0; l < kLanes; ++l) {
    double d[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        d[3 * i + j] = P.r[3 * i][l] * N.r[3 * j][l] + P.r[3 * i + 1][l] * N.r[3 * j + 1][l] +
                       P.r[3 * i + 2][l] * N.r[3 * j + 2][l];
    for (int i = 0; i < 3; ++i) res[i][l] = P.t[i][l] - N.t[i][l];
    res[3][l] = 0.5 * (d[7] - d[5]);
    res[4][l] = 0.5 * (d[2] - d[6]);
    res[5][l] = 0.5 * (d[3] - d[1]);
    sin_t[l] = std::sqrt(res[3][l] * res[3][l] + res[4][l] * res[4][l] + res[5][l] * res[5][l]);
    cos_t[l] = 0.5 * (d[0] + d[4] + d[8] - 1.0);
  }
  // `&`, not `&&`: one vector comparison, not a branch per lane.
  MTCAL_VECTORIZE_LOOP
  for (int l = 0; l < kLanes; ++l) small = small & (sin_t[l] < 1e-2) & (cos_t[l] > 0.0);
  if (small) {
    // theta / sin(theta) = asin(s) / s = 1 + s^2/6 + 3 s^4/40 + 5 s^6/112 + 35 s^8/1152 + ...;
    // for s < 1e-2 the omitted terms are below 1e-21 relative.
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      const double s2 = sin_t[l] * sin_t[l];
      const double f = 1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0 + s2 * (35.0 / 1152.0))));
      res[3][l] *= f;
      res[4][l] *= f;
      res[5][l] *= f;
    }
  } else {
    for (int l = 0; l < kLanes; ++l) {
      Mat3 dR;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          dR(i, j) = P.r[3 * i][l] * N.r[3 * j][l] + P.r[3 * i + 1][l] * N.r[3 * j + 1][l] +
                     P.r[3 * i + 2][l] * N.r[3 * j + 2][l];
      const Vec3 rv = rotation_vector(dR);
      for (int i = 0; i < 3; ++i) res[3 + i][l] = rv[i];
    }
  }
  for (std::size_t l = 0; l < count; ++l)
    for (int c = 0; c < 6; ++c) out[l * 6 + c] = res[c][l];
}

// Whether a block's positions reach beyond kSincosLaneLimit for some axis' sines and cosines.
[[gnu::always_inline]] inline bool needs_libm(const ErrorModel::Program::AxisInfo& a, const AxisLanes& L) {
  bool big = false;
  MTCAL_VECTORIZE_LOOP
  for (int l = 0; l < kLanes; ++l) big = big | !(std::fabs(L.q[l]) * a.sincos_scale <= detail::kSincosLaneLimit);
  return big;
}

template <bool Libm>
[[gnu::always_inline]] inline void run_block_body(const ErrorModel::Program& prog, AxisLanes* ax, std::size_t count,
                                                  double* out) {
  for (std::size_t k = 0; k < prog.axes.size(); ++k) prepare_axis<Libm>(prog.axes[k], ax[k]);
  Block P, N;
  run_program<Libm>(prog, ax, prog.actual_ops, P, true);
  run_program<Libm>(prog, ax, prog.nominal_ops, N, false);
  finish_block(P, N, count, out);
}

[[gnu::always_inline]] inline void run_block_impl(const ErrorModel::Program& prog, const double* q,
                                                  const std::int8_t* dir, std::size_t count, double* out) {
  const std::size_t n = prog.axes.size();
  AxisLanes ax[6];
  bool libm = false;
  for (std::size_t k = 0; k < n; ++k) {
    AxisLanes& L = ax[k];
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      const std::size_t src = std::min<std::size_t>(static_cast<std::size_t>(l), count - 1);
      L.q[l] = q[src * n + k];
      L.dir[l] = dir ? static_cast<double>(dir[src * n + k]) : 0.0;
    }
    libm = libm | needs_libm(prog.axes[k], L);
  }
  if (libm)
    run_block_body<true>(prog, ax, count, out);
  else
    run_block_body<false>(prog, ax, count, out);
}

// A Joint or Motion op of the factor of one axis of a grid, per grid value (lane): the tables
// hold the factor's rotation (row-major) and translation, SoA: tab[c * count + j], c < 12.
[[gnu::always_inline]] inline void axis_factors_impl(const ErrorModel::Program& prog, std::size_t k,
                                                     const std::vector<double>& v, const std::vector<Op>& ops,
                                                     std::size_t begin, std::size_t end, bool actual, double* tab) {
  AxisLanes ax[6]{};  // the segment's ops read axis k only
  const std::size_t count = v.size();
  for (std::size_t j0 = 0; j0 < count; j0 += kLanes) {
    AxisLanes& L = ax[k];
    MTCAL_VECTORIZE_LOOP
    for (std::size_t l = 0; l < kLanes; ++l) {
      L.q[l] = v[std::min(j0 + l, count - 1)];
      L.dir[l] = 0.0;  // a grid has no directions of motion
    }
    Block B;
    if (needs_libm(prog.axes[k], L)) {
      prepare_axis<true>(prog.axes[k], L);
      run_program<true>(prog, ax, ops, B, actual, begin, end);
    } else {
      prepare_axis<false>(prog.axes[k], L);
      run_program<false>(prog, ax, ops, B, actual, begin, end);
    }
    for (std::size_t l = 0; l < kLanes && j0 + l < count; ++l) {
      for (std::size_t c = 0; c < 9; ++c) tab[c * count + j0 + l] = B.r[c][l];
      for (std::size_t c = 0; c < 3; ++c) tab[(9 + c) * count + j0 + l] = B.t[c][l];
    }
  }
}

// A rigid transform of one configuration, rotation row-major.
struct Pose {
  double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double t[3] = {0, 0, 0};
};

// out = a * F_j, F from a factor table of `count` values.
inline void compose(const Pose& a, const double* tab, std::size_t count, std::size_t j, Pose& out) {
  double f[12];
  for (std::size_t c = 0; c < 12; ++c) f[c] = tab[c * count + j];
  for (int i = 0; i < 3; ++i) {
    const double x = a.r[3 * i], y = a.r[3 * i + 1], z = a.r[3 * i + 2];
    for (int c = 0; c < 3; ++c) out.r[3 * i + c] = x * f[c] + y * f[3 + c] + z * f[6 + c];
    out.t[i] = a.t[i] + (x * f[9] + y * f[10] + z * f[11]);
  }
}

// One block of 8 configurations of a row: the poses A * Fa[l] and N * Fn[l] lane by lane, then the
// same output step as run_block. fa and fn point at the block's first value in tables of `stride`
// values a row (12 rows: rotation row-major, translation).
[[gnu::always_inline]] inline void grid_block(const Pose& A, const Pose& N, const double* fa, const double* fn,
                                              std::size_t stride, std::size_t len, double* out) {
  // The two rotation products written out apart: as one helper called for each pose (or a loop
  // choosing pose and table at run time) the AVX2 level ran 1.2-1.5x slower (measured).
  Block P, Q;
  for (int i = 0; i < 3; ++i) {
    const double x = A.r[3 * i], y = A.r[3 * i + 1], z = A.r[3 * i + 2];
    for (int c = 0; c < 3; ++c) {
      const double* f0 = fa + c * stride;
      const double* f1 = fa + (3 + c) * stride;
      const double* f2 = fa + (6 + c) * stride;
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) P.r[3 * i + c][l] = x * f0[l] + y * f1[l] + z * f2[l];
    }
  }
  for (int i = 0; i < 3; ++i) {
    const double x = N.r[3 * i], y = N.r[3 * i + 1], z = N.r[3 * i + 2];
    for (int c = 0; c < 3; ++c) {
      const double* f0 = fn + c * stride;
      const double* f1 = fn + (3 + c) * stride;
      const double* f2 = fn + (6 + c) * stride;
      MTCAL_VECTORIZE_LOOP
      for (int l = 0; l < kLanes; ++l) Q.r[3 * i + c][l] = x * f0[l] + y * f1[l] + z * f2[l];
    }
  }
  // The translation error as a sum of differences, not a difference of two tool positions
  // (hundreds of mm): A.R (fa.t - fn.t) + (A.R - N.R) fn.t + (A.t - N.t) keeps the rounding
  // at the size of the terms that differ.
  Lane dft[3];
  const double* ftn[3] = {fn + 9 * stride, fn + 10 * stride, fn + 11 * stride};
  for (std::size_t c = 0; c < 3; ++c) {
    const double* fat = fa + (9 + c) * stride;
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) dft[c][l] = fat[l] - ftn[c][l];
  }
  for (int i = 0; i < 3; ++i) {
    const double x = A.r[3 * i], y = A.r[3 * i + 1], z = A.r[3 * i + 2];
    const double u = x - N.r[3 * i], v = y - N.r[3 * i + 1], w = z - N.r[3 * i + 2], d = A.t[i] - N.t[i];
    MTCAL_VECTORIZE_LOOP
    for (int l = 0; l < kLanes; ++l) {
      P.t[i][l] =
          (x * dft[0][l] + y * dft[1][l] + z * dft[2][l]) + (u * ftn[0][l] + v * ftn[1][l] + w * ftn[2][l]) + d;
      Q.t[i][l] = 0.0;
    }
  }
  finish_block(P, Q, len, out);
}

// Configurations (outer, l) for l in [l0, l1) of the fastest axis, tables of `count` values a row.
// Full blocks read the tables in place; a short last block reads a copy whose missing lanes
// repeat its last value.
[[gnu::always_inline]] inline void grid_row_impl(const Pose& A, const Pose& N, const double* fa, const double* fn,
                                                 std::size_t count, std::size_t l0, std::size_t l1, double* out) {
  std::size_t b = l0;
  for (; b + kLanes <= l1; b += kLanes) grid_block(A, N, fa + b, fn + b, count, kLanes, out + (b - l0) * 6);
  if (b == l1) return;
  double ta[12 * kLanes], tn[12 * kLanes];
  for (std::size_t c = 0; c < 12; ++c)
    MTCAL_VECTORIZE_LOOP
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::size_t j = std::min(b + l, l1 - 1);
      ta[c * kLanes + l] = fa[c * count + j];
      tn[c * kLanes + l] = fn[c * count + j];
    }
  grid_block(A, N, ta, tn, kLanes, l1 - b, out + (b - l0) * 6);
}

// Each kernel once per instruction-set level (util/kernel.hpp); the bodies are the always-inlined
// functions above, so every level runs the same operations in the same order.
#define MTCAL_KERNEL_LEVEL(ATTR, SUFFIX)                                                                           \
  ATTR void run_block_##SUFFIX(const ErrorModel::Program& prog, const double* q, const std::int8_t* dir,          \
                               std::size_t count, double* out) {                                                 \
    run_block_impl(prog, q, dir, count, out);                                                                    \
  }                                                                                                              \
  ATTR void axis_factors_##SUFFIX(const ErrorModel::Program& prog, std::size_t k, const std::vector<double>& v,   \
                                  const std::vector<Op>& ops, std::size_t begin, std::size_t end, bool actual,    \
                                  double* tab) {                                                                 \
    axis_factors_impl(prog, k, v, ops, begin, end, actual, tab);                                                 \
  }                                                                                                              \
  ATTR void grid_row_##SUFFIX(const Pose& A, const Pose& N, const double* fa, const double* fn, std::size_t count, \
                              std::size_t l0, std::size_t l1, double* out) {                                     \
    grid_row_impl(A, N, fa, fn, count, l0, l1, out);                                                             \
  }

MTCAL_KERNEL_LEVEL(, baseline)
#if MTCAL_KERNEL_DISPATCH
MTCAL_KERNEL_LEVEL(MTCAL_TARGET_AVX2, avx2)
MTCAL_KERNEL_LEVEL(MTCAL_TARGET_AVX512, avx512)
#endif
#undef MTCAL_KERNEL_LEVEL

struct Kernels {
  decltype(&run_block_baseline) run_block;
  decltype(&axis_factors_baseline) axis_factors;
  decltype(&grid_row_baseline) grid_row;
};

// The kernels of the level in use (kernel_isa.hpp).
Kernels kernels() {
  switch (kernel_isa()) {
#if MTCAL_KERNEL_DISPATCH
    case KernelIsa::Avx512:
      return {run_block_avx512, axis_factors_avx512, grid_row_avx512};
    case KernelIsa::Avx2:
      return {run_block_avx2, axis_factors_avx2, grid_row_avx2};
#endif
    default:
      return {run_block_baseline, axis_factors_baseline, grid_row_baseline};
  }
}

}  // namespace

bool ErrorModel::grid_structured() const { return program_->grid_structured; }

// Operation counts of the lane code above, per configuration (one lane); each constant is counted
// from the function it names.
namespace {
constexpr double kFlopsMul = 63;         // mul_const / mul_block: 3 rows x (3 x (3 mul + 2 add) + 3 mul + 3 add)
constexpr double kFlopsRotation = 18;    // mul_rotation: 3 rows x (4 mul + 2 add)
constexpr double kFlopsTranslation = 6;  // mul_translation: 3 rows x (mul + add)
constexpr double kFlopsSincos = 43;      // sincos_lane: reduction 9, z 1, sine 13, cosine 15, quadrant 5
constexpr double kFlopsErrorBlock = 3 * kFlopsSincos + 20;  // error_block: three sincos, 20 for the rotation
constexpr double kFlopsFinish = 76;      // finish_block: R_a R_n^T 45, differences 9, norms 10, series 12

double form_flops(const detail::LaneForm& f) {
  switch (f.kind) {
    case detail::LaneForm::Kind::Polynomial:
      return 8;  // Horner 3 mul + 3 add, reversal mul + add
    case detail::LaneForm::Kind::Fourier:
      // constant + reversal 2, the sines' sum 1; per harmonic h*q, sincos, 2 mul + 2 add
      return 3 + static_cast<double>(f.harmonics()) * (kFlopsSincos + 5);
    case detail::LaneForm::Kind::Table:
      return f.backward.empty() ? 7 : 13;  // weights 4 (2 sub, div, sub), value 3 (9 with both runs)
  }
  return 0;
}
}  // namespace

double ErrorModel::batch_flops_per_configuration() const {
  const Program& prog = *program_;
  double flops = kFlopsFinish;
  for (const auto& a : prog.axes) flops += a.rotary ? 1 + kFlopsSincos + 6 : 3;  // prepare_axis
  for (const auto* ops : {&prog.actual_ops, &prog.nominal_ops})
    for (const Op& op : *ops) {
      if (op.kind == Op::Kind::Const) {
        flops += kFlopsMul;
      } else if (op.kind == Op::Kind::Joint) {
        flops += prog.axes[static_cast<std::size_t>(op.axis)].rotary ? kFlopsRotation : kFlopsTranslation;
      } else {
        for (const auto& f : prog.axes[static_cast<std::size_t>(op.axis)].forms) flops += form_flops(f);
        flops += kFlopsErrorBlock + kFlopsMul;
      }
    }
  return flops;
}

double ErrorModel::grid_flops_per_configuration() const {
  if (!program_->grid_structured) return batch_flops_per_configuration();
  // grid_row: the two rotation products with the prefix 2 x 45, the translation error 39; then
  // finish_block. The factors and prefix products are computed once per grid value or digit.
  return 2 * 45 + 39 + kFlopsFinish;
}

void ErrorModel::evaluate_grid(std::span<const std::vector<double>> values, std::size_t first, std::span<double> out,
                               const BatchOptions& options) const {
  const std::size_t n = axis_count();
  if (values.size() != n)
    throw ModelError("grid of " + std::to_string(values.size()) + " axes for a machine with " + std::to_string(n));
  std::size_t total = 1;
  for (const auto& v : values) {
    if (v.empty()) throw ModelError("grid axis without values");
    total *= v.size();
  }
  const std::size_t count = out.size() / 6;
  if (out.size() % 6 != 0 || first > total || count > total - first)
    throw ModelError("grid output of " + std::to_string(out.size()) + " values from configuration " +
                     std::to_string(first) + " does not fit a grid of " + std::to_string(total));
  if (count == 0) return;
  const Program& prog = *program_;
  const Kernels kern = kernels();
  if (!prog.grid_structured) {  // point by point, in slices of bounded memory
    constexpr std::size_t kSlice = 1 << 14;
    std::vector<double> q(std::min(count, kSlice) * n);
    for (std::size_t s = 0; s < count; s += kSlice) {
      const std::size_t len = std::min(kSlice, count - s);
      for (std::size_t r = 0; r < len; ++r) {
        std::size_t index = first + s + r;
        for (std::size_t k = n; k-- > 0;) {
          q[r * n + k] = values[k][index % values[k].size()];
          index /= values[k].size();
        }
      }
      evaluate_batch(std::span(q).first(len * n), {}, out.subspan(s * 6, len * 6), options);
    }
    return;
  }
  // Each axis' factor once per grid value; the constants before axis 0 go into axis 0's factor.
  std::vector<std::vector<double>> act(n), nom(n);
  for (std::size_t k = 0; k < n; ++k) {
    act[k].resize(12 * values[k].size());
    nom[k].resize(12 * values[k].size());
    kern.axis_factors(prog, k, values[k], prog.actual_ops, k ? prog.actual_segment[k] : 0,
                 prog.actual_segment[k + 1], true, act[k].data());
    kern.axis_factors(prog, k, values[k], prog.nominal_ops, k ? prog.nominal_segment[k] : 0,
                 prog.nominal_segment[k + 1], false, nom[k].data());
  }
  const std::size_t last = values[n - 1].size();
  auto work = [&](std::size_t b, std::size_t e) {
    // Prefix products over the outer axes 0..n-2 (axis n-2 varies fastest among them).
    std::size_t digit[6] = {};
    Pose pa[6], pn[6];
    std::size_t outer = (first + b) / last;
    for (std::size_t k = n - 1; k-- > 0;) {
      digit[k] = outer % values[k].size();
      outer /= values[k].size();
    }
    auto rebuild = [&](std::size_t from) {
      for (std::size_t k = from; k + 1 < n; ++k) {
        compose(k ? pa[k - 1] : Pose{}, act[k].data(), values[k].size(), digit[k], pa[k]);
        compose(k ? pn[k - 1] : Pose{}, nom[k].data(), values[k].size(), digit[k], pn[k]);
      }
    };
    rebuild(0);
    const Pose identity;
    for (std::size_t i = b; i < e;) {
      check_interrupt();  // one range per thread: parallel_for's own check comes too late
      const std::size_t l0 = (first + i) % last, l1 = std::min(last, l0 + (e - i));
      kern.grid_row(n > 1 ? pa[n - 2] : identity, n > 1 ? pn[n - 2] : identity, act[n - 1].data(), nom[n - 1].data(), last,
               l0, l1, out.data() + i * 6);
      i += l1 - l0;
      if (i >= e || n == 1) continue;
      std::size_t k = n - 2;
      while (++digit[k] == values[k].size() && k > 0) digit[k--] = 0;
      rebuild(k);
    }
  };
  std::size_t threads = worker_count(options.threads, count);
  threads = std::min(threads, std::max<std::size_t>(1, count / 4096));
  parallel_for_ranges(count, threads, static_cast<int>(threads),
                      [&](std::size_t b, std::size_t e, std::size_t) { work(b, e); });
}

ErrorModel::ErrorModel(const Machine& machine) : machine_(machine), program_(std::make_unique<Program>(machine_)) {
  if (machine_.axes.size() > 6) throw ModelError("at most 6 axes are supported");
}
ErrorModel::~ErrorModel() = default;
ErrorModel::ErrorModel(const ErrorModel& o) : machine_(o.machine_), program_(std::make_unique<Program>(*o.program_)) {}
ErrorModel& ErrorModel::operator=(const ErrorModel& o) {
  if (this != &o) {
    machine_ = o.machine_;
    program_ = std::make_unique<Program>(*o.program_);
  }
  return *this;
}
ErrorModel::ErrorModel(ErrorModel&&) noexcept = default;
ErrorModel& ErrorModel::operator=(ErrorModel&&) noexcept = default;

void ErrorModel::evaluate_batch(std::span<const double> q, std::span<const std::int8_t> dir, std::span<double> out,
                                const BatchOptions& options) const {
  const std::size_t n = axis_count();
  if (q.size() % n != 0)
    throw ModelError("joint array of " + std::to_string(q.size()) + " values is not a multiple of " +
                     std::to_string(n) + " axes");
  const std::size_t count = q.size() / n;
  if (!dir.empty() && dir.size() != q.size())
    throw ModelError("direction array has " + std::to_string(dir.size()) + " values, expected " +
                     std::to_string(q.size()));
  if (out.size() != count * 6)
    throw ModelError("output array has " + std::to_string(out.size()) + " values, expected " +
                     std::to_string(count * 6));
  const std::size_t blocks = (count + kLanes - 1) / kLanes;
  const Kernels kern = kernels();
  auto work = [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      if ((b - b0) % 1024 == 0) check_interrupt();  // one range per thread: parallel_for's check comes too late
      const std::size_t first = b * kLanes;
      const std::size_t len = std::min<std::size_t>(kLanes, count - first);
      kern.run_block(*program_, q.data() + first * n, dir.empty() ? nullptr : dir.data() + first * n, len,
                out.data() + first * 6);
    }
  };
  std::size_t threads = worker_count(options.threads, blocks);
  // Below a few thousand configurations a thread costs more than it saves.
  threads = std::min(threads, std::max<std::size_t>(1, blocks / 256));
  // One contiguous range of blocks per thread: every block is computed alone, so the split
  // does not change a result.
  parallel_for_ranges(blocks, threads, static_cast<int>(threads),
                      [&](std::size_t b0, std::size_t b1, std::size_t) { work(b0, b1); });
}

}  // namespace mtcal
