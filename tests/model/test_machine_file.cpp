// Machine files: every shipped example loads and round-trips; every bad input is rejected with
// file, line and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <string>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"

using namespace mtcal;

namespace {

const char* kExamples[] = {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"};

std::string machine_file_example(const char* name) { return std::string(MTCAL_EXAMPLES_DIR) + "/" + name; }

const char* kGood = R"(mtcal_machine: 1
name: test
topology: wCBXfYZt
axes:
  X: {travel: [-300, 300]}
  Y: {travel: [-250, 250]}
  Z: {travel: [-300, 300]}
  B: {travel: [-180, 180], point: [0, 0, 100]}
  C: {point: [0, 0, 100]}
errors:
  EXX: {unit: um, argument_unit: m, polynomial: [0, 5], reversal: 1}
  EC0Y: 12 um/m
  EX0C: {value: 3, unit: um}
)";

// Replaces the first occurrence of `from` in kGood.
std::string with(const std::string& from, const std::string& to) {
  std::string s = kGood;
  auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return s.replace(p, from.size(), to);
}

// Parses text expected to fail; returns the error.
InputError bad(const std::string& text) {
  try {
    parse_machine(text, "bad.yaml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError({}, "");
}

}  // namespace

TEST(MachineFile, GoodFileLoadsWithUnitsConverted) {
  Machine m = parse_machine(kGood, "good.yaml");
  EXPECT_EQ(m.topology.chain, "wCBXfYZt");
  ASSERT_EQ(m.axes.size(), 5u);
  EXPECT_TRUE(m.axes[0].moves_workpiece);                            // C
  EXPECT_FALSE(m.axes[3].moves_workpiece);                           // Y
  EXPECT_NEAR(m.axes[1].travel->max, 3.14159265358979, 1e-12);       // deg -> rad
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EXX.1")), 5e-6);  // 5 um/m -> mm/mm
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EXX.b")), 1e-3);
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EC0Y")), 12e-6);
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EX0C")), 3e-3);
  EXPECT_FALSE(m.parameter_index("EZ0C"));  // along the C axis line: not a parameter
}

TEST(MachineFile, ExamplesLoadAndRoundTrip) {
  for (const char* name : kExamples) {
    SCOPED_TRACE(name);
    const Machine m = load_machine(machine_file_example(name));
    EXPECT_FALSE(m.name.empty());
    const Machine back = parse_machine(to_yaml(m), "roundtrip");
    const auto a = m.parameters(), b = back.parameters();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].name, b[i].name);
      EXPECT_EQ(a[i].value, b[i].value) << a[i].name;
    }
    // Same evaluations everywhere (geometry and travel survive too).
    const auto q = mtcal::testing::random_configurations(m, 50, 7);
    const ErrorModel ma(m), mb(back);
    const std::size_t n = m.axes.size();
    for (std::size_t r = 0; r < 50; ++r) {
      std::span<const double> qr(q.data() + r * n, n);
      const auto ea = ma.evaluate(qr), eb = mb.evaluate(qr);
      EXPECT_LE((ea.translation - eb.translation).norm(), 1e-15);
      EXPECT_LE((ea.rotation - eb.rotation).norm(), 1e-18);
    }
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_EQ(m.axes[k].travel.has_value(), back.axes[k].travel.has_value());
      if (m.axes[k].travel) {
        EXPECT_EQ(m.axes[k].travel->max, back.axes[k].travel->max);
      }
    }
  }
}

TEST(MachineFile, ExampleMachinesHaveTheErrorsTheyPromise) {
  // The 3-axis example has all 21 errors non-zero: 18 motion errors and 3 squareness errors.
  const Machine m = load_machine(machine_file_example("vmc-3axis.yaml"));
  std::set<std::string> nonzero;
  for (const auto& p : m.parameters())
    if (p.value != 0.0) nonzero.insert(p.error.str());
  EXPECT_EQ(nonzero.size(), 21u);
  // The RRTTT example carries Viprey's 61 parameters: 30 motion, 19 location, 12 mounting.
  const Machine v = load_machine(machine_file_example("rrttt-table-table.yaml"));
  std::map<ErrorKind, std::set<std::string>> by_kind;
  for (const auto& p : v.parameters())
    if (p.value != 0.0) by_kind[p.error.kind].insert(p.error.str());
  EXPECT_EQ(by_kind[ErrorKind::Motion].size(), 30u);
  EXPECT_EQ(by_kind[ErrorKind::Location].size(), 19u);
  EXPECT_EQ(by_kind[ErrorKind::Mounting].size(), 12u);
}

TEST(MachineFile, AcceptsGreekMuEmptySectionsAndKeepsTheDescription) {
  const std::string text = with("EC0Y: 12 um/m", "EC0Y: 12 \xCE\xBCm/m") + "tool:\ndescription: a test machine\n";
  const Machine m = parse_machine(text, "good.yaml");
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EC0Y")), 12e-6);
  EXPECT_EQ(m.description, "a test machine");
  EXPECT_EQ(parse_machine(to_yaml(m), "again").description, "a test machine");
  const Machine empty =
      parse_machine("mtcal_machine: 1\ntopology: wXfYZt\naxes: {X: , Y: , Z: }\nerrors:\n", "empty.yaml");
  for (const auto& p : empty.parameters()) EXPECT_EQ(p.value, 0.0) << p.name;
}

TEST(MachineFile, ReportsTheFirstBadEntryInFileOrder) {
  // Two bad errors: the one written first is reported, not the alphabetically first.
  InputError e =
      bad(with("EC0Y: 12 um/m", "EZX: {unit: furlong, polynomial: [1]}\n  EAX: {unit: furlong, polynomial: [1]}"));
  EXPECT_EQ(e.where().field, "errors.EZX.unit") << e.what();
}

TEST(MachineFile, MissingFileIsAnInputError) { EXPECT_THROW(load_machine("/nonexistent/machine.yaml"), InputError); }

struct BadCase {
  const char* name;
  std::string text;
  int line;             // expected 1-based line, 0: don't check
  const char* field;    // expected field (dotted key path), "" : don't check
  const char* message;  // substring of the message
};

// Each case fails with file, line (when given), field (when given) and a message part.
template <class Parse>
void expect_bad_cases(const std::vector<BadCase>& cases, const std::string& file, Parse&& parse) {
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    InputError e = parse(c.text);
    EXPECT_EQ(e.where().file, file);
    if (c.line) {
      EXPECT_EQ(e.where().line, c.line) << e.what();
    }
    if (*c.field) {
      EXPECT_EQ(e.where().field, c.field) << e.what();
    }
    EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
}

TEST(MachineFile, BadInputsNameFileLineAndKey) {
  const std::vector<BadCase> cases = {
      {"unknown top-level key", with("name: test", "nmae: test"), 2, "nmae", "unknown key"},
      {"unknown axis key", with("X: {travel", "X: {travle: [1, 2], travel"), 5, "axes.X.travle", "unknown key"},
      {"unknown error name", with("EC0Y: 12 um/m", "EQY: 12 um/m"), 12, "errors.EQY", "unknown error name"},
      {"duplicated error", with("EC0Y: 12 um/m", "EC0Y: 12 um/m\n  EC0Y: 13 um/m"), 13, "errors.EC0Y", "duplicated"},
      {"bad unit", with("12 um/m", "12 furlongs"), 12, "errors.EC0Y", "unknown unit 'furlongs'"},
      {"hexadecimal number", with("polynomial: [0, 5]", "polynomial: [0, 0x10]"), 11, "errors.EXX.polynomial.1",
       "finite number"},
      {"two documents", std::string(kGood) + "---\nname: other\n", 15, "", "one YAML document"},
      {"direction of another axis", with("C: {point", "C: {direction: +x, point"), 9, "axes.C.direction",
       "'+z' or '-z'"},
      {"slope as joint angle unit", with("axes:", "units: {angle: um/m}\naxes:"), 4, "units.angle", "slope"},
      {"argument unit of a Fourier series",
       with("EC0Y: 12 um/m", "ECC: {unit: urad, argument_unit: deg, fourier: {cos: [1]}}"), 12,
       "errors.ECC.argument_unit", "Fourier"},
      {"non-plain key", with("name: test", "? [a, b]\n: test"), 2, "", "plain key"},
      {"negative tool length", with("errors:", "tool: {length: -5}\nerrors:"), 10, "tool.length", ">= 0"},
      {"length unit for an angle", with("12 um/m", "12 um"), 12, "errors.EC0Y", "unit"},
      {"missing unit", with("12 um/m", "12"), 12, "errors.EC0Y", "number"},
      {"non-numeric value", with("polynomial: [0, 5]", "polynomial: [0, five]"), 11, "errors.EXX.polynomial.1",
       "finite number"},
      {"non-numeric travel", with("[-300, 300]}\n  Y", "[-300, lots]}\n  Y"), 5, "axes.X.travel.1", "finite number"},
      {"axis not in topology (axes)", with("  Z: {travel: [-300, 300]}", "  Z: {travel: [-300, 300]}\n  A: {}"), 8,
       "axes.A", "not in topology"},
      {"axis not in topology (error)", with("EC0Y: 12 um/m", "EAA: {unit: urad, polynomial: [1]}"), 12, "errors.EAA",
       "not in topology"},
      {"location not allowed", with("EC0Y: 12 um/m", "EZ0C: 12 um"), 12, "errors.EZ0C", "not a location error"},
      {"missing axis", with("  Y: {travel: [-250, 250]}\n", ""), 5, "axes", "missing"},
      {"bad topology", with("wCBXfYZt", "wCBXYZt"), 3, "topology", "'f'"},
      {"wrong version", with("mtcal_machine: 1", "mtcal_machine: 2"), 1, "mtcal_machine", "version"},
      {"no version", with("mtcal_machine: 1\n", ""), 0, "", "mtcal_machine"},
      {"invalid YAML", with("name: test", "name: [test"), 0, "", "YAML"},
      {"two motion forms",
       with("polynomial: [0, 5]", "polynomial: [0, 5], table: {positions: [0, 1], forward: [0, 0]}"), 11, "errors.EXX",
       "exactly one"},
      {"too many coefficients", with("[0, 5]", "[0, 5, 0, 0, 1]"), 11, "errors.EXX.polynomial", "1 to 4"},
      {"table not increasing",
       with("EC0Y: 12 um/m", "EYY: {unit: um, table: {positions: [0, 5, 5], forward: [0, 1, 2]}}"), 12,
       "errors.EYY.table.positions", "increase"},
      {"table length mismatch",
       with("EC0Y: 12 um/m", "EYY: {unit: um, table: {positions: [0, 5], forward: [0, 1, 2]}}"), 12,
       "errors.EYY.table.forward", "expected 2 values"},
      {"fourier on linear", with("EC0Y: 12 um/m", "EYY: {unit: um, fourier: {cos: [1]}}"), 12, "errors.EYY.fourier",
       "rotary"},
      {"bad direction", with("C: {point", "C: {direction: up, point"), 9, "axes.C.direction", "direction"},
      {"travel reversed", with("[-300, 300]}\n  Y", "[300, -300]}\n  Y"), 5, "axes.X.travel", "min < max"},
      {"point needs 3 numbers", with("point: [0, 0, 100]}\n  C", "point: [0, 100]}\n  C"), 8, "axes.B.point",
       "3 numbers"},
      {"infinite value", with("polynomial: [0, 5]", "polynomial: [0, .inf]"), 11, "errors.EXX.polynomial.1", "finite"},
  };
  expect_bad_cases(cases, "bad.yaml", bad);
}

// ---- Parameter files (load_parameters / apply_parameters) ----

namespace {

std::map<std::string, double> parameter_map(const Machine& m) {
  std::map<std::string, double> out;
  for (const auto& p : m.parameters()) out[p.name] = p.value;
  return out;
}

// Applies text expected to fail to a machine loaded from kGood; returns the error.
InputError bad_params(const std::string& text) {
  Machine m = parse_machine(kGood, "good.yaml");
  try {
    apply_parameters(m, text, "params.yaml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError({}, "");
}

}  // namespace

TEST(ParameterFile, ReplacesExactlyTheNamedErrors) {
  // Every one of the 61 errors of this example is non-zero, so an accidental change shows.
  Machine m = load_machine(machine_file_example("rrttt-table-table.yaml"));
  const auto before = parameter_map(m);
  const std::string name = m.name, chain = m.topology.chain;
  apply_parameters(m,
                   "mtcal_parameters: 1\n"
                   "description: C axis from a probing run\n"
                   "errors:\n"
                   "  EX0C: 12 um\n"
                   "  EA0C: {value: 25, unit: urad}  # a comment\n"
                   "  EXX: {unit: um, argument_unit: m, polynomial: [0, 5]}\n"
                   "  EXt: -3 um\n"
                   "  ECw: 0 urad\n",
                   "p.yaml");
  const auto after = parameter_map(m);
  ASSERT_EQ(before.size(), after.size());
  EXPECT_DOUBLE_EQ(after.at("EX0C"), 12e-3);
  EXPECT_DOUBLE_EQ(after.at("EA0C"), 25e-6);
  EXPECT_DOUBLE_EQ(after.at("EXt"), -3e-3);
  EXPECT_EQ(after.at("ECw"), 0.0);
  // A motion error is replaced as a whole: the coefficients and reversal it does not give are 0.
  EXPECT_EQ(after.at("EXX.0"), 0.0);
  EXPECT_DOUBLE_EQ(after.at("EXX.1"), 5e-6);
  EXPECT_EQ(after.at("EXX.2"), 0.0);
  EXPECT_EQ(after.at("EXX.3"), 0.0);
  EXPECT_EQ(after.at("EXX.b"), 0.0);
  const std::set<std::string> replaced = {"EX0C", "EA0C", "EXt", "ECw", "EXX.0", "EXX.1", "EXX.2", "EXX.3", "EXX.b"};
  for (const auto& [n, v] : before) {
    if (replaced.count(n)) {
      if (n != "EXX.0") {  // EXX.0 was 0 already
        EXPECT_NE(after.at(n), v) << n << " should have changed";
      }
      continue;
    }
    EXPECT_EQ(after.at(n), v) << n << " changed";
  }
  EXPECT_EQ(m.name, name);
  EXPECT_EQ(m.topology.chain, chain);
  EXPECT_EQ(m.axis('C').location[index_of(Component::X)], 12e-3);
}

TEST(ParameterFile, LaterFilesWinAndEmptyFilesChangeNothing) {
  Machine m = parse_machine(kGood, "good.yaml");
  const std::string yaml = to_yaml(m);
  apply_parameters(m, "mtcal_parameters: 1\n", "empty.yaml");
  apply_parameters(m, "mtcal_parameters: 1\nerrors:\n", "empty-errors.yaml");
  apply_parameters(m, "mtcal_parameters: 1\nerrors: {}\n", "empty-map.yaml");
  EXPECT_EQ(to_yaml(m), yaml);
  apply_parameters(m, "mtcal_parameters: 1\nerrors: {EX0C: 7 um, EY0C: 1 um}\n", "a.yaml");
  apply_parameters(m, "mtcal_parameters: 1\nerrors: {EX0C: -2 um}\n", "b.yaml");
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EX0C")), -2e-3);
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EY0C")), 1e-3);
}

TEST(ParameterFile, RespectsUnits) {
  const Machine base = parse_machine(kGood, "good.yaml");
  // With units, the argument of a polynomial is in those units (no argument_unit given).
  Machine m = base;
  apply_parameters(m,
                   "mtcal_parameters: 1\n"
                   "units: {length: m, angle: rad}\n"
                   "errors:\n"
                   "  EXX: {unit: um, polynomial: [0, 5, 2]}\n"
                   "  ECC: {unit: urad, polynomial: [0, 3]}\n"
                   "  EX0C: 3 um\n",
                   "units.yaml");
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EXX.1")), 5e-6);  // 5 um/m
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EXX.2")), 2e-9);  // 2 um/m^2 in mm/mm^2
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("ECC.1")), 3e-6);  // 3 urad/rad
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EX0C")), 3e-3);   // a quantity carries its unit
  // Without units: mm and deg, as in a machine file.
  Machine d = base;
  apply_parameters(d,
                   "mtcal_parameters: 1\n"
                   "errors:\n"
                   "  EXX: {unit: um, polynomial: [0, 5]}\n"
                   "  ECC: {unit: urad, polynomial: [0, 3]}\n",
                   "defaults.yaml");
  EXPECT_DOUBLE_EQ(d.parameter(*d.parameter_index("EXX.1")), 5e-3);                                   // 5 um/mm
  EXPECT_DOUBLE_EQ(d.parameter(*d.parameter_index("ECC.1")), 3e-6 / (3.14159265358979323846 / 180));  // urad/deg
  // argument_unit still overrides units.
  Machine a = base;
  apply_parameters(a,
                   "mtcal_parameters: 1\nunits: {length: m}\nerrors:\n"
                   "  EXX: {unit: um, argument_unit: mm, polynomial: [0, 5]}\n",
                   "arg.yaml");
  EXPECT_DOUBLE_EQ(a.parameter(*a.parameter_index("EXX.1")), 5e-3);
  // The defaults are the parameter file's own, not the machine file's.
  Machine in_m = parse_machine(with("axes:", "units: {length: m, angle: rad}\naxes:"), "m-units.yaml");
  apply_parameters(in_m, "mtcal_parameters: 1\nerrors:\n  EXX: {unit: um, polynomial: [0, 5]}\n", "p.yaml");
  EXPECT_DOUBLE_EQ(in_m.parameter(*in_m.parameter_index("EXX.1")), 5e-3);
}

TEST(ParameterFile, BadInputsNameFileLineAndField) {
  const std::string head = "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n";
  const std::vector<BadCase> cases = {
      {"missing mtcal_parameters", "description: x\nerrors:\n  EX0C: 12 um\n", 1, "", "missing key 'mtcal_parameters'"},
      {"machine file instead", kGood, 1, "mtcal_machine", "unknown key"},
      {"wrong version", "mtcal_parameters: 2\nerrors:\n  EX0C: 12 um\n", 1, "mtcal_parameters",
       "unsupported format version 2"},
      {"description not text", "mtcal_parameters: 1\ndescription: {a: 1}\n", 2, "description", "expected text"},
      {"non-numeric version", "mtcal_parameters: one\n", 1, "mtcal_parameters", "finite number"},
      {"unknown top-level key", "mtcal_parameters: 1\nname: x\nerrors:\n  EX0C: 12 um\n", 2, "name",
       "unknown key 'name'"},
      {"misspelt errors", "mtcal_parameters: 1\nerorrs:\n  EX0C: 12 um\n", 2, "erorrs", "unknown key"},
      {"unknown error name", head + "  EQQ: 1 um\n", 4, "errors.EQQ", "unknown error name 'EQQ'"},
      {"parameter name, not error name", head + "  EXX.1: 1 um\n", 4, "errors.EXX.1", "unknown error name"},
      {"location error of an axis not in topology", head + "  EY0A: 1 um\n", 4, "errors.EY0A",
       "not in topology wCBXfYZt"},
      {"motion error of an axis not in topology", head + "  EAA: {unit: urad, polynomial: [1]}\n", 4, "errors.EAA",
       "not in topology"},
      {"location error the axis does not have", head + "  EZ0C: 1 um\n", 4, "errors.EZ0C", "not a location error"},
      {"bad unit", head + "  EY0C: 1 furlong\n", 4, "errors.EY0C", "unknown unit 'furlong'"},
      {"angle unit for a length", head + "  EY0C: 1 urad\n", 4, "errors.EY0C", "length unit"},
      {"bad unit in a map", head + "  EY0C: {value: 1, unit: furlong}\n", 4, "errors.EY0C.unit",
       "unknown unit 'furlong'"},
      {"bad units section", "mtcal_parameters: 1\nunits: {length: furlong}\nerrors:\n  EX0C: 12 um\n", 2,
       "units.length", "unknown unit 'furlong'"},
      {"slope as units.angle", "mtcal_parameters: 1\nunits: {angle: um/m}\n", 2, "units.angle", "slope"},
      {"unknown units key", "mtcal_parameters: 1\nunits: {time: s}\n", 2, "units.time", "unknown key"},
      {"missing unit", head + "  EY0C: 12\n", 4, "errors.EY0C", "number"},
      {"non-numeric value", head + "  EY0C: twelve um\n", 4, "errors.EY0C", "expected a number before the unit"},
      {"non-numeric value in a map", head + "  EY0C: {value: twelve, unit: um}\n", 4, "errors.EY0C.value",
       "finite number"},
      {"non-numeric coefficient", head + "  EXX: {unit: um, polynomial: [0, five]}\n", 4, "errors.EXX.polynomial.1",
       "finite number"},
      {"infinite value", head + "  EY0C: {value: .inf, unit: um}\n", 4, "errors.EY0C.value", "finite"},
      {"duplicated error", head + "  EX0C: 13 um\n", 4, "errors.EX0C", "duplicated"},
      {"errors not a map", "mtcal_parameters: 1\nerrors: [EX0C]\n", 2, "errors", "expected a map"},
      {"fourier on a linear axis", head + "  EYY: {unit: um, fourier: {cos: [1]}}\n", 4, "errors.EYY.fourier",
       "rotary"},
      {"two documents", head + "---\nmtcal_parameters: 1\n", 5, "", "one YAML document"},
      {"invalid YAML", head + "  EY0C: [1\n", 0, "", "YAML"},
  };
  expect_bad_cases(cases, "params.yaml", bad_params);
}

TEST(ParameterFile, AllOrNothing) {
  const Machine original = load_machine(machine_file_example("rrttt-table-table.yaml"));
  const std::string yaml = to_yaml(original);
  const auto params = parameter_map(original);
  // Each has good errors before the bad one; the machine must keep none of them.
  const std::vector<std::string> failing = {
      "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n  EXX: {unit: um, polynomial: [0, 5]}\n  EQQ: 1 um\n",
      "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n  EY0C: 1 furlong\n",
      "mtcal_parameters: 1\nerrors:\n  EXt: 1 um\n  ECC: {unit: urad, polynomial: [0, x]}\n",
      "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n  EX0B: 1 um\n",
      "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n  EX0C: 13 um\n",
      "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\nbogus: 1\n",
      "mtcal_parameters: 2\nerrors:\n  EX0C: 12 um\n",
      "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n---\nmtcal_parameters: 1\n",
  };
  for (const auto& text : failing) {
    SCOPED_TRACE(text);
    Machine m = original;
    EXPECT_THROW(apply_parameters(m, text, "p.yaml"), InputError);
    EXPECT_EQ(to_yaml(m), yaml);
    EXPECT_EQ(parameter_map(m), params);
  }
}

TEST(ParameterFile, LoadParametersReadsAFileAndNamesItInErrors) {
  const auto dir = std::filesystem::temp_directory_path() / ("mtcal-params-" + std::to_string(std::random_device{}()));
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "good.yaml").string(), bad_file = (dir / "bad.yaml").string();
  std::ofstream(good) << "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n";
  std::ofstream(bad_file) << "mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n  EQQ: 1 um\n";
  Machine m = parse_machine(kGood, "good.yaml");
  load_parameters(m, good);
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EX0C")), 12e-3);
  const std::string yaml = to_yaml(m);
  try {
    load_parameters(m, bad_file);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, bad_file);
    EXPECT_EQ(e.where().line, 4);
    EXPECT_EQ(e.where().field, "errors.EQQ");
  }
  EXPECT_EQ(to_yaml(m), yaml);
  EXPECT_THROW(load_parameters(m, (dir / "missing.yaml").string()), InputError);
  std::filesystem::remove_all(dir);
}

// yaml-cpp 0.7 loops forever (growing memory) on a ',' outside a flow collection, and /dev/zero
// never ends: both are refused at once, naming the line or the limit.
TEST(MachineFile, PathologicalYamlIsRefusedAtOnce) {
  for (const std::string text : {",", "  ,", ",,", "name: a\n---\n,", "- 1\n,"}) {
    try {
      mtcal::parse_machine(text, "bad.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const mtcal::InputError& e) {
      EXPECT_EQ(e.where().file, "bad.yaml");
      EXPECT_GE(e.where().line, 1);
      EXPECT_NE(std::string(e.what()).find("YAML"), std::string::npos) << e.what();
    }
  }
  try {
    mtcal::load_machine("/dev/zero");
    ADD_FAILURE() << "/dev/zero accepted";
  } catch (const mtcal::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("16 MiB"), std::string::npos) << e.what();
  }
}
