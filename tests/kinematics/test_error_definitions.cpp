// Every single error of every example machine (and of synthetic machines of many topologies,
// also with reversed axes) acts on the tool as its definition says: the exact model's
// sensitivities about the error-free machine equal an independent small-displacement derivation
// (tests/testing/small_displacement.cpp) built from the definitions in docs/conventions.md.
#include <gtest/gtest.h>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "small_displacement.hpp"
#include "synthetic.hpp"

using namespace mtcal;

namespace {

void expect_definitions_hold(Machine m, std::uint64_t seed) {
  m.clear_errors();
  const ErrorModel model(m);
  const auto q = mtcal::testing::random_configurations(m, 4, seed);
  const std::size_t n = m.axes.size();
  for (std::size_t r = 0; r < 4; ++r) {
    std::span<const double> qr(q.data() + r * n, n);
    const auto exact = model.error_sensitivities(qr);
    const auto defined = mtcal::testing::small_displacement_effects(m, qr);
    ASSERT_EQ(exact.size(), defined.size());
    for (std::size_t i = 0; i < exact.size(); ++i) {
      ASSERT_EQ(exact[i].error, defined[i].error);
      const double scale = std::max(1.0, defined[i].effect.norm());
      EXPECT_LE((exact[i].effect - defined[i].effect).norm(), 1e-10 * scale)
          << m.name << " " << exact[i].error.str() << " config " << r << "\nexact   " << exact[i].effect.transpose()
          << "\ndefined " << defined[i].effect.transpose();
    }
  }
}

}  // namespace

TEST(ErrorDefinitions, EveryErrorOfEveryExampleMachine) {
  for (const char* f : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"}) {
    SCOPED_TRACE(f);
    expect_definitions_hold(load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + f), 3);
  }
}

TEST(ErrorDefinitions, EveryErrorOfManyTopologiesAndReversedAxes) {
  for (const char* topo :
       {"wXYfZt", "wfXYZt", "wCBXfYZt", "wCAYXfZt", "wXfYZCAt", "wfXYZBCt", "wBfXYZCt", "wABCfXYZt"}) {
    for (bool reversed : {false, true}) {
      SCOPED_TRACE(std::string(topo) + (reversed ? " reversed" : ""));
      expect_definitions_hold(mtcal::testing::nominal_machine(topo, reversed), 5);
    }
  }
}
