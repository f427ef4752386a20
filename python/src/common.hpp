// Pieces every binding file of the Python module shares: JSON to Python, checked NumPy inputs, exceptions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mtcal/io/json/json.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {
class ReportMetadata;
}  // namespace mtcal

namespace mtcal::python {

namespace py = pybind11;

// The library's JSON (io/*_json.hpp) as Python objects: objects become dicts in the same key
// order, arrays lists, null None. What every result's to_dict() returns, so its keys are those
// of the command's --json.
py::object to_py(const Json& j);

// A (rows, cols) table of doubles read from a Python object. When the object is already a
// C-contiguous float64 NumPy array its own buffer is used (no copy; `array` keeps it alive);
// any other real-valued array-like is converted once. Refuses, with ValueError naming `name`:
// a dtype that is not real numbers (complex, object, str, bool), a wrong number of dimensions or
// columns, and (finite == true) NaN or infinity.
struct Rows {
  py::array_t<double> array;
  const double* data = nullptr;
  std::size_t rows = 0, cols = 0;
  bool single = false;  // a 1-D input taken as one row
  std::span<const double> span() const { return {data, rows * cols}; }
};
// cols: the required column count, or nullopt for any. allow_single: a 1-D array of cols values
// is one row (single = true).
Rows as_rows(py::handle obj, const char* name, std::optional<std::size_t> cols, bool allow_single, bool finite = true);
// A 1-D array of doubles (any length unless size is given); same rules.
Rows as_vector(py::handle obj, const char* name, std::optional<std::size_t> size = std::nullopt, bool finite = true);
std::vector<double> as_std_vector(py::handle obj, const char* name, std::optional<std::size_t> size = std::nullopt);

// Directions of motion, (rows, cols) of -1, 0, +1. An int8 C-contiguous array is used in place;
// other integer (or exactly integral float) arrays are converted. ValueError naming `name` for a
// wrong shape, dtype or value.
struct Directions {
  py::array_t<std::int8_t> array;
  const std::int8_t* data = nullptr;
  std::size_t size = 0;
  std::span<const std::int8_t> span() const { return {data, size}; }
};
Directions as_directions(py::handle obj, const char* name, std::size_t rows, std::size_t cols, bool single);

// A new C-contiguous float64 array of this shape.
py::array_t<double> new_array(std::vector<py::ssize_t> shape);
// A copy of doubles as an array of this shape (rows x cols when cols > 0, else 1-D).
py::array_t<double> to_array(std::span<const double> values, std::size_t cols = 0);
py::array_t<double> to_array(const Vec3& v);
py::array_t<std::int8_t> to_int8_array(std::span<const std::int8_t> values, std::size_t cols);

// A grid argument: the CLI's text "X=0:500:21,..." (mm, deg) or a mapping axis letter -> values in
// internal units (axes not named held at 0). Per axis values, chain order, internal units.
std::vector<std::vector<double>> grid_values(const Machine& m, py::handle grid, const char* name);

// A Python 'configurations' argument in internal units (mm, rad) as one std::vector row.
std::vector<double> configuration(const Machine& m, py::handle obj, const char* name);

// Test metadata (a report's --meta fields) as a dict key -> value, in the record's order
// (acceptance_reports.cpp).
py::dict metadata_dict(const ReportMetadata& m);

// The mtcal exception classes (mtcal.Error, mtcal.InputError, mtcal.ModelError) and the
// translation of the library's exceptions into them, the message unchanged.
void register_exceptions(py::module_& m);

// The binding groups, one translation unit each.
void bind_model(py::module_& m);
void bind_evaluation(py::module_& m);
void bind_probing_identification(py::module_& m);
void bind_prediction_compensation(py::module_& m);

// Runs a long computation without the GIL, stoppable with Ctrl-C. Without the GIL, Python's own
// SIGINT handler only records the signal and nothing acts on it until the computation returns;
// while a LongCall lives, SIGINT asks the library's parallel loops to stop instead
// (request_interrupt), they throw mtcal::Interrupted and the module raises KeyboardInterrupt.
// The previous handler is put back when the last LongCall of the process ends.
class LongCall {
 public:
  LongCall();
  ~LongCall();
  LongCall(const LongCall&) = delete;
  LongCall& operator=(const LongCall&) = delete;

 private:
  py::gil_scoped_release release_;
};

}  // namespace mtcal::python
