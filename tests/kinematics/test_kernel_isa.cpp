// The batched kernel's instruction-set levels (baseline, AVX2, AVX-512) give the same bits, and its
// lane-wise motion-error forms agree with MotionFunction::value: tables and polynomials bit for
// bit, Fourier series within the sine/cosine's ulp.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdio>
#include <string>
#include <vector>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>

#include "../../src/kinematics/lane_forms.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/kinematics/kernel_isa.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"

using namespace mtcal;
using detail::kLanes;
using detail::LaneForm;

namespace {

// Restores the level in use when a test that switches levels ends.
class IsaGuard {
 public:
  IsaGuard() : saved_(kernel_isa()) {}
  ~IsaGuard() { set_kernel_isa(saved_); }
  IsaGuard(const IsaGuard&) = delete;
  IsaGuard& operator=(const IsaGuard&) = delete;

 private:
  KernelIsa saved_;
};

// A random Fourier series of `terms` cosine and sine terms of amplitude `scale`.
MotionFunction random_fourier(std::mt19937_64& rng, std::size_t cos_terms, std::size_t sin_terms, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Fourier f;
  f.constant = u(rng);
  f.reversal = u(rng) * 0.1;
  for (std::size_t k = 0; k < cos_terms; ++k) f.cos_terms.push_back(u(rng));
  for (std::size_t k = 0; k < sin_terms; ++k) f.sin_terms.push_back(u(rng) / static_cast<double>(k + 1));
  return MotionFunction(f);
}

// A random table of n increasing positions over [lo, hi], with a backward table when asked.
MotionFunction random_table(std::mt19937_64& rng, std::size_t n, double lo, double hi, double scale, bool backward) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Table t;
  double x = lo;
  const double step = (hi - lo) / static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) {
    t.positions.push_back(x);
    x += step * (0.5 + u(rng));  // uneven spacing: the search must not assume a uniform table
    t.forward.push_back(scale * (2 * u(rng) - 1));
    if (backward) t.backward.push_back(scale * (2 * u(rng) - 1));
  }
  return MotionFunction(t);
}

// The five-axis HU40T topology with every motion error non-zero, its forms mixed: polynomials,
// Fourier series (rotary axes) and tables with and without a backward run, over and beyond the
// travels so that the held end values are reached.
Machine mixed_forms_machine(std::uint64_t seed) {
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  mtcal::testing::randomize_errors(m, seed);
  std::mt19937_64 rng(seed);
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    Axis& ax = m.axes[k];
    const double lo = ax.travel ? ax.travel->min : -std::numbers::pi;
    const double hi = ax.travel ? ax.travel->max : std::numbers::pi;
    const double inset = 0.1 * (hi - lo);
    for (std::size_t c = 0; c < 6; ++c) {
      const double scale = c < 3 ? 2e-3 : 1e-5;  // mm, rad
      switch ((k + c) % 3) {
        case 0:
          break;  // randomize_errors' polynomial
        case 1:
          ax.motion[c] = ax.kind == AxisKind::Rotary ? random_fourier(rng, 1 + c, 3, scale)
                                                     : random_table(rng, 7 + 5 * c, lo + inset, hi - inset, scale, true);
          break;
        default:
          ax.motion[c] = random_table(rng, 2 + 13 * c, lo + inset, hi - inset, scale, c % 2 == 0);
          break;
      }
    }
  }
  return m;
}

std::vector<Machine> machines_to_compare() {
  std::vector<Machine> out;
  for (const char* f : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"})
    out.push_back(load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + f));
  out.push_back(mixed_forms_machine(3));
  out.push_back(mixed_forms_machine(4));
  return out;
}

// Directions -1, 0 and +1: a zero direction takes a table's mean of both runs.
void mix_in_zero_directions(std::vector<std::int8_t>& dir) {
  for (std::size_t i = 0; i < dir.size(); i += 3) dir[i] = 0;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// On every level, evaluate_batch of q (and dir, when given) against ErrorModel::evaluate
// (MotionFunction::value per error) to 1e-12 mm and 1e-15 rad.
void expect_every_level_agrees_with_the_scalar_model(const ErrorModel& model, const std::vector<double>& q,
                                                      const std::vector<std::int8_t>& dir) {
  const std::size_t n = model.axis_count(), N = q.size() / n;
  for (KernelIsa isa : supported_kernel_isas()) {
    SCOPED_TRACE(std::string(to_string(isa)));
    set_kernel_isa(isa);
    std::vector<double> out(N * 6);
    model.evaluate_batch(q, dir, out, BatchOptions{1});
    for (std::size_t r = 0; r < N; ++r) {
      const auto e = model.evaluate(std::span(q).subspan(r * n, n),
                                    dir.empty() ? std::span<const std::int8_t>() : std::span(dir).subspan(r * n, n));
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(out[r * 6 + c], e.translation[c], 1e-12) << "row " << r << ", first axis " << q[r * n];
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(out[r * 6 + 3 + c], e.rotation[c], 1e-15) << "row " << r << ", first axis " << q[r * n];
    }
  }
}

}  // namespace

TEST(KernelIsa, NamesRoundTripAndUnknownNamesAreRefused) {
  for (KernelIsa isa : {KernelIsa::Baseline, KernelIsa::Avx2, KernelIsa::Avx512}) {
    const auto back = parse_kernel_isa(to_string(isa));
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(*back, isa);
  }
  EXPECT_FALSE(parse_kernel_isa("AVX2").has_value());
  EXPECT_FALSE(parse_kernel_isa("").has_value());
  EXPECT_FALSE(parse_kernel_isa("sse4").has_value());
}

TEST(KernelIsa, BaselineIsAlwaysSupportedAndTheLevelInUseIsSupported) {
  const auto levels = supported_kernel_isas();
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.front(), KernelIsa::Baseline);
  EXPECT_TRUE(kernel_isa_supported(kernel_isa()));
  for (KernelIsa isa : {KernelIsa::Avx2, KernelIsa::Avx512}) {
    if (!kernel_isa_supported(isa)) {
      EXPECT_THROW(set_kernel_isa(isa), ModelError);
    }
  }
  // AVX-512 implies AVX2 here: a level is never offered without the ones below it.
  if (kernel_isa_supported(KernelIsa::Avx512)) {
    EXPECT_TRUE(kernel_isa_supported(KernelIsa::Avx2));
  }
}

TEST(KernelIsa, EveryLevelGivesTheSameBitsForPointLists) {
  const IsaGuard guard;
  const auto levels = supported_kernel_isas();
  std::printf("kernel levels on this processor:");
  for (KernelIsa isa : levels) std::printf(" %s", std::string(to_string(isa)).c_str());
  std::printf("\n");
  for (const Machine& m : machines_to_compare()) {
    SCOPED_TRACE(m.name);
    const ErrorModel model(m);
    std::vector<std::int8_t> dir;
    const std::size_t N = 4099;  // not a multiple of the 8 lanes
    const auto q = mtcal::testing::random_configurations(m, N, 17, &dir);
    mix_in_zero_directions(dir);
    set_kernel_isa(KernelIsa::Baseline);
    std::vector<double> reference(N * 6);
    model.evaluate_batch(q, dir, reference, BatchOptions{1});
    for (KernelIsa isa : levels) {
      SCOPED_TRACE(std::string(to_string(isa)));
      set_kernel_isa(isa);
      std::vector<double> out(N * 6);
      model.evaluate_batch(q, dir, out, BatchOptions{2});
      EXPECT_TRUE(same_bits(out, reference));
      // Without directions as well (the tables' mean, no reversal).
      std::vector<double> a(N * 6), b(N * 6);
      model.evaluate_batch(q, {}, a, BatchOptions{1});
      set_kernel_isa(KernelIsa::Baseline);
      model.evaluate_batch(q, {}, b, BatchOptions{1});
      EXPECT_TRUE(same_bits(a, b));
    }
  }
}

TEST(KernelIsa, EveryLevelGivesTheSameBitsForGrids) {
  const IsaGuard guard;
  for (const Machine& m : machines_to_compare()) {
    SCOPED_TRACE(m.name);
    const ErrorModel model(m);
    std::vector<std::vector<double>> values;
    std::size_t total = 1;
    for (const Axis& ax : m.axes) {
      const double lo = ax.travel ? ax.travel->min : -std::numbers::pi;
      const double hi = ax.travel ? ax.travel->max : std::numbers::pi;
      const std::size_t count = m.axes.size() > 3 ? 7 : 19;
      std::vector<double> v;
      for (std::size_t i = 0; i < count; ++i)
        v.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(count - 1));
      total *= count;
      values.push_back(v);
    }
    set_kernel_isa(KernelIsa::Baseline);
    std::vector<double> reference(total * 6);
    model.evaluate_grid(values, 0, reference, BatchOptions{1});
    for (KernelIsa isa : supported_kernel_isas()) {
      SCOPED_TRACE(std::string(to_string(isa)));
      set_kernel_isa(isa);
      std::vector<double> out(total * 6);
      model.evaluate_grid(values, 0, out, BatchOptions{2});
      EXPECT_TRUE(same_bits(out, reference));
    }
  }
}

TEST(KernelIsa, MixedFormsAgreeWithTheScalarModel) {
  // The whole chain with Fourier and table forms against ErrorModel::evaluate (MotionFunction::value
  // per error), on every level.
  const IsaGuard guard;
  const Machine m = mixed_forms_machine(5);
  std::vector<std::int8_t> dir;
  const auto q = mtcal::testing::random_configurations(m, 301, 23, &dir);
  mix_in_zero_directions(dir);
  expect_every_level_agrees_with_the_scalar_model(ErrorModel(m), q, dir);
}

namespace {

// f at 8 lanes of (q, dir) through the lane code.
std::array<double, kLanes> lanes(const MotionFunction& f, const std::array<double, kLanes>& q,
                                 const std::array<double, kLanes>& dir) {
  const LaneForm form(f);
  double ql[kLanes], dl[kLanes], out[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    ql[l] = q[static_cast<std::size_t>(l)];
    dl[l] = dir[static_cast<std::size_t>(l)];
  }
  detail::motion_lanes(form, ql, dl, out);
  std::array<double, kLanes> r{};
  for (int l = 0; l < kLanes; ++l) r[static_cast<std::size_t>(l)] = out[l];
  return r;
}

// Positions to try on a table: its nodes, midpoints, just inside and outside each node, beyond
// both ends, and signed zeros.
std::vector<double> probe_positions(const Table& t) {
  std::vector<double> q = {0.0, -0.0};
  const double inf = std::numeric_limits<double>::infinity();
  for (double x : t.positions) {
    q.push_back(x);
    q.push_back(std::nextafter(x, inf));
    q.push_back(std::nextafter(x, -inf));
  }
  for (std::size_t i = 0; i + 1 < t.positions.size(); ++i) q.push_back(0.5 * (t.positions[i] + t.positions[i + 1]));
  q.push_back(t.positions.front() - 1e3);
  q.push_back(t.positions.back() + 1e3);
  q.push_back(-inf);
  q.push_back(inf);
  return q;
}

}  // namespace

TEST(LaneForms, TablesGiveTheBitsOfTheScalarFormEverywhere) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t n : {2u, 3u, 4u, 5u, 9u, 16u, 17u, 33u, 1000u, 1025u}) {
    for (bool backward : {false, true}) {
      SCOPED_TRACE(std::to_string(n) + (backward ? " with backward" : " forward only"));
      const MotionFunction f = random_table(rng, n, -400.0, 350.0, 5e-3, backward);
      const Table& t = std::get<Table>(f.form());
      std::vector<double> qs = probe_positions(t);
      for (int i = 0; i < 2000; ++i) qs.push_back(-500.0 + 1000.0 * u(rng));
      for (std::size_t i = 0; i < qs.size(); i += kLanes) {
        std::array<double, kLanes> q{}, dir{};
        for (std::size_t l = 0; l < kLanes; ++l) {
          q[l] = qs[std::min(i + l, qs.size() - 1)];
          dir[l] = static_cast<double>(static_cast<int>((i + l) % 3) - 1);
        }
        const auto got = lanes(f, q, dir);
        for (std::size_t l = 0; l < kLanes; ++l) {
          const double want = f.value(q[l], static_cast<int>(dir[l]));
          EXPECT_EQ(std::bit_cast<std::uint64_t>(got[l]), std::bit_cast<std::uint64_t>(want))
              << "q = " << q[l] << " dir = " << dir[l] << ": lanes " << got[l] << ", scalar " << want;
        }
      }
    }
  }
}

TEST(LaneForms, NaNPositionsGiveNaNAsTheScalarForm) {
  std::mt19937_64 rng(5);
  const MotionFunction f = random_table(rng, 6, 0.0, 10.0, 1.0, true);
  std::array<double, kLanes> q{}, dir{};
  q.fill(std::numeric_limits<double>::quiet_NaN());
  dir = {1, -1, 0, 1, -1, 0, 1, 0};
  for (double v : lanes(f, q, dir)) EXPECT_TRUE(std::isnan(v));
  EXPECT_TRUE(std::isnan(f.value(q[0], 1)));
}

TEST(LaneForms, PolynomialsGiveTheBitsOfTheScalarForm) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Polynomial p;
    for (double& c : p.coefficients) c = u(rng) * std::pow(10.0, -3 - 3 * trial % 9);
    p.reversal = trial % 4 == 0 ? 0.0 : u(rng) * 1e-3;
    const MotionFunction f(p);
    std::array<double, kLanes> q{}, dir{};
    for (std::size_t l = 0; l < kLanes; ++l) {
      q[l] = trial % 5 == 0 ? 0.0 : 500.0 * u(rng);
      dir[l] = static_cast<double>(static_cast<int>(l % 3) - 1);
    }
    const auto got = lanes(f, q, dir);
    for (std::size_t l = 0; l < kLanes; ++l)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(got[l]),
                std::bit_cast<std::uint64_t>(f.value(q[l], static_cast<int>(dir[l]))));
  }
}

TEST(LaneForms, FourierSeriesAgreeWithTheScalarFormWithinTheirTermsUlp) {
  // Each term's cosine or sine differs from the C library's by about 1 ulp, so the sum may differ by
  // a few ulp of the sum of the terms' magnitudes, never more.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;  // in units of eps * sum |terms|
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t nc = static_cast<std::size_t>(trial % 7), ns = static_cast<std::size_t>((trial / 7) % 9);
    const MotionFunction f = random_fourier(rng, nc, ns, trial % 3 == 0 ? 1e-9 : 1e-4);
    const Fourier& s = std::get<Fourier>(f.form());
    double magnitude = std::abs(s.constant) + std::abs(s.reversal);
    for (double a : s.cos_terms) magnitude += std::abs(a);
    for (double b : s.sin_terms) magnitude += std::abs(b);
    std::array<double, kLanes> q{}, dir{};
    for (std::size_t l = 0; l < kLanes; ++l) {
      // Within a turn, several turns (continuous rotary axes), exact zero and multiples of pi/2.
      q[l] = l == 0 ? 0.0 : l == 1 ? std::numbers::pi / 2 : (u(rng) - 0.5) * (trial % 2 ? 2 * std::numbers::pi : 200.0);
      dir[l] = static_cast<double>(static_cast<int>(l % 3) - 1);
    }
    const auto got = lanes(f, q, dir);
    for (std::size_t l = 0; l < kLanes; ++l) {
      const double want = f.value(q[l], static_cast<int>(dir[l]));
      const double err = std::abs(got[l] - want) / (std::numeric_limits<double>::epsilon() * magnitude);
      worst = std::max(worst, err);
      EXPECT_LE(err, 4.0) << "q = " << q[l] << ": lanes " << got[l] << ", scalar " << want;
    }
  }
  std::printf("largest Fourier difference: %.2f eps x sum of |terms|\n", worst);
}

TEST(LaneForms, ZeroFormsGiveExactZeros) {
  std::array<double, kLanes> q{}, dir{};
  for (std::size_t l = 0; l < kLanes; ++l) {
    q[l] = -3.0 + static_cast<double>(l);
    dir[l] = static_cast<double>(static_cast<int>(l % 3) - 1);
  }
  Table t{{-1.0, 0.0, 2.0}, {0.0, 0.0, 0.0}, {}};
  for (const MotionFunction& f : {MotionFunction(Polynomial{}), MotionFunction(Fourier{0.0, {0.0, 0.0}, {0.0}, 0.0}),
                                  MotionFunction(t)})
    for (double v : lanes(f, q, dir)) EXPECT_EQ(v, 0.0);
}

TEST(KernelFlops, FormsChangeTheCountByTheirOwnOperations) {
  // The count walks the compiled program: replacing one polynomial by another form changes it by
  // exactly the two forms' counts (a polynomial 8; a Fourier series 3 + 48 per harmonic; a table
  // 7, or 13 with a backward run), the rest of the program being the same.
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  mtcal::testing::randomize_errors(m, 2);
  const double base = ErrorModel(m).batch_flops_per_configuration();
  EXPECT_GT(base, 1000.0);
  Machine fourier = m;
  fourier.axes[0].motion[5] = MotionFunction(Fourier{0.0, {1e-6, 2e-6}, {1e-6, 0.0, 3e-6}, 0.0});  // 3 harmonics
  EXPECT_EQ(ErrorModel(fourier).batch_flops_per_configuration(), base - 8 + 3 + 3 * 48);
  Machine table = m;
  table.axes[2].motion[0] = MotionFunction(Table{{-1.0, 0.0, 1.0}, {0.0, 1e-3, 0.0}, {}});
  EXPECT_EQ(ErrorModel(table).batch_flops_per_configuration(), base - 8 + 7);
  table.axes[2].motion[1] = MotionFunction(Table{{-1.0, 1.0}, {0.0, 1e-3}, {1e-3, 0.0}});
  EXPECT_EQ(ErrorModel(table).batch_flops_per_configuration(), base - 16 + 7 + 13);
  // The grid kernel's work per configuration does not depend on the forms.
  EXPECT_EQ(ErrorModel(fourier).grid_flops_per_configuration(), 205.0);
  EXPECT_EQ(ErrorModel(m).grid_flops_per_configuration(), 205.0);
}

TEST(KernelFlops, AnErrorFreeMachineCountsTheNominalChainTwice) {
  // Without errors the actual program is the nominal one (error-free slots are skipped), so the
  // count is the output step plus the joints' preparation plus twice one program's operations.
  const Machine m = mtcal::testing::nominal_machine("wXYfZt");
  const double flops = ErrorModel(m).batch_flops_per_configuration();
  const double program = (flops - 76 - 3 * 3) / 2;  // output step 76, three linear joints 3 each
  EXPECT_EQ(program, std::floor(program));
  // At least the three joint translations (6 each), at most those and one constant product around
  // each (63 each).
  EXPECT_GE(program, 3 * 6.0);
  EXPECT_LE(program, 3 * 6.0 + 4 * 63.0);
}

TEST(KernelIsa, HugeRotaryAnglesTakeTheCLibrarysSineAndCosine) {
  // Beyond 2^22 rad the kernel's own reduction by pi/2 loses digits (at 1e16 rad a Fourier term
  // was off by 1e-3 relative, at 1e20 by 1e23): a block holding such an angle (joint or harmonic)
  // is run with std::sin and std::cos, on every level, and agrees with the scalar model.
  const IsaGuard guard;
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  for (auto& ax : m.axes) ax.travel.reset();
  m.axes[0].motion[5] = MotionFunction(Fourier{0.0, {1e-5, 2e-6}, {1e-5}, 0.0});  // C: ECC, 3 harmonics
  m.axes[0].motion[0] = MotionFunction(Fourier{0.0, {1e-3}, {}, 0.0});           // C: EXC
  const ErrorModel model(m);
  std::vector<double> q;
  for (double c : {0.5, 1.5e6, 3e7, 1e9, 1e16, 1e20, -4.5e12, 2.0})  // 1.5e6 x 3 harmonics: beyond too
    for (double v : {c, 0.3, 10.0, 20.0, -30.0}) q.push_back(v);
  expect_every_level_agrees_with_the_scalar_model(model, q, {});
}

TEST(LaneForms, EdgeBitsOfTablesAndSeries) {
  // A table whose last interval's width overflows: the end weights are still exact.
  const MotionFunction wide(Table{{-1e308, 1e308}, {1.0, 2.0}, {}});
  // A -0 at a first position 0, with a -0 first value and a negative second one.
  const MotionFunction zero(Table{{0.0, 1.0}, {-0.0, -1.0}, {}});
  // A series of signed zeros and no sine term.
  const MotionFunction series(Fourier{-0.0, {}, {}, -0.0});
  std::array<double, kLanes> q = {1e308, std::numeric_limits<double>::infinity(), -1e308, 0.0, -0.0, 5e307, -5e307,
                                  1.0};
  std::array<double, kLanes> dir = {0, 0, 0, 0, 0, 0, 0, 0};
  for (const MotionFunction* f : {&wide, &zero, &series}) {
    const auto got = lanes(*f, q, dir);
    for (std::size_t l = 0; l < kLanes; ++l)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(got[l]), std::bit_cast<std::uint64_t>(f->value(q[l], 0)))
          << "q = " << q[l] << ": lanes " << got[l] << ", scalar " << f->value(q[l], 0);
  }
}
