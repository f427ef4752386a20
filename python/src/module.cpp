// The Python module mtcal._mtcal: JSON conversion, checked NumPy inputs, exceptions, and the binding groups.
#include <cmath>
#include <cstring>
#include <csignal>
#include <exception>
#include <mutex>

#include "common.hpp"
#include "mtcal/io/text/number_format.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/interrupt.hpp"
#include "mtcal/version.hpp"

namespace mtcal::python {

// The binding groups declared here rather than in common.hpp, so that adding one recompiles module.cpp alone.
void bind_measurements(py::module_& m);
void bind_history(py::module_& m);
void bind_acceptance_reports(py::module_& m);
void bind_planning(py::module_& m);
void bind_rehearsal(py::module_& m);

py::object to_py(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return py::none();
    case Json::value_t::boolean: return py::bool_(j.get<bool>());
    case Json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case Json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case Json::value_t::number_float: return py::float_(j.get<double>());
    // Python's str is Unicode: bytes that are not UTF-8 become U+FFFD, as in the --json text.
    case Json::value_t::string: return py::str(utf8_text(j.get_ref<const std::string&>()));
    case Json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(to_py(e));
      return l;
    }
    case Json::value_t::object: {
      py::dict d;
      for (const auto& [key, value] : j.items()) d[py::str(utf8_text(key))] = to_py(value);
      return d;
    }
    default: return py::none();
  }
}

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

py::array as_numpy(py::handle obj, const char* name) {
  if (obj.is_none()) throw py::value_error(std::string(name) + ": expected an array of numbers, found None");
  try {
    return py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw py::value_error(std::string(name) + ": expected an array of numbers (" + e.what() + ")");
  }
}

// Real numbers only: float or integer kinds.
void check_real(const py::array& a, const char* name) {
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::value_error(std::string(name) + ": expected real numbers (float64), found dtype " +
                          std::string(py::str(a.dtype())));
}

void check_finite(const double* p, std::size_t rows, std::size_t cols, const char* name) {
  for (std::size_t i = 0; i < rows * cols; ++i)
    if (!std::isfinite(p[i])) {
      const std::size_t r = i / cols, c = i % cols;
      throw py::value_error(std::string(name) + ": expected finite numbers, found " + std::to_string(p[i]) +
                            " at row " + std::to_string(r) + ", column " + std::to_string(c));
    }
}

}  // namespace

Rows as_rows(py::handle obj, const char* name, std::optional<std::size_t> cols, bool allow_single, bool finite) {
  py::array a = as_numpy(obj, name);
  check_real(a, name);
  const std::string want = cols ? "(N, " + std::to_string(*cols) + ")" : std::string("(N, k)");
  Rows r;
  if (a.ndim() == 1 && allow_single) {
    r.single = true;
  } else if (a.ndim() != 2) {
    throw py::value_error(std::string(name) + ": expected an array of shape " + want +
                          (allow_single ? " or (" + (cols ? std::to_string(*cols) : std::string("k")) + ",)" : "") +
                          ", found shape " + shape_text(a));
  }
  // The same buffer when it is already C-contiguous float64; one converted copy otherwise.
  r.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!r.array) throw py::error_already_set();
  r.rows = r.single ? 1 : static_cast<std::size_t>(r.array.shape(0));
  r.cols = static_cast<std::size_t>(r.array.shape(r.single ? 0 : 1));
  if (cols && r.cols != *cols)
    throw py::value_error(std::string(name) + ": expected an array of shape " + want + ", found shape " +
                          shape_text(a));
  r.data = r.array.data();
  if (finite) {
    LongCall release;  // without the GIL, stoppable with Ctrl-C
    check_finite(r.data, r.rows, r.cols, name);
  }
  return r;
}

Rows as_vector(py::handle obj, const char* name, std::optional<std::size_t> size, bool finite) {
  py::array a = as_numpy(obj, name);
  check_real(a, name);
  if (a.ndim() != 1 || (size && static_cast<std::size_t>(a.shape(0)) != *size))
    throw py::value_error(std::string(name) + ": expected an array of shape (" +
                          (size ? std::to_string(*size) : std::string("N")) + ",), found shape " + shape_text(a));
  Rows r;
  r.array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  r.rows = 1;
  r.cols = static_cast<std::size_t>(a.shape(0));
  r.single = true;
  r.data = r.array.data();
  if (finite) check_finite(r.data, 1, r.cols, name);
  return r;
}

std::vector<double> as_std_vector(py::handle obj, const char* name, std::optional<std::size_t> size) {
  const Rows r = as_vector(obj, name, size);
  return {r.data, r.data + r.cols};
}

Directions as_directions(py::handle obj, const char* name, std::size_t rows, std::size_t cols, bool single) {
  py::array a = as_numpy(obj, name);
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u' && kind != 'f')
    throw py::value_error(std::string(name) + ": expected directions -1, 0, +1 (int8), found dtype " +
                          std::string(py::str(a.dtype())));
  const bool shape_ok = single ? (a.ndim() == 1 && static_cast<std::size_t>(a.shape(0)) == cols)
                               : (a.ndim() == 2 && static_cast<std::size_t>(a.shape(0)) == rows &&
                                  static_cast<std::size_t>(a.shape(1)) == cols);
  if (!shape_ok)
    throw py::value_error(
        std::string(name) + ": expected an array of shape " +
        (single ? "(" + std::to_string(cols) + ",)" : "(" + std::to_string(rows) + ", " + std::to_string(cols) + ")") +
        " like the configurations, found shape " + shape_text(a));
  Directions d;
  if (a.dtype().is(py::dtype::of<std::int8_t>())) {
    d.array = py::array_t<std::int8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  } else {
    // Checked before the conversion so that 256 or 0.5 cannot wrap or truncate into a direction.
    py::array_t<double, py::array::c_style | py::array::forcecast> v =
        py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    for (py::ssize_t i = 0; i < v.size(); ++i) {
      const double x = v.data()[i];
      if (x != -1.0 && x != 0.0 && x != 1.0)
        throw py::value_error(std::string(name) + ": expected -1, 0 or +1, found " + std::to_string(x) +
                              " at flat index " + std::to_string(i));
    }
    d.array = py::array_t<std::int8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  }
  d.data = d.array.data();
  d.size = static_cast<std::size_t>(d.array.size());
  for (std::size_t i = 0; i < d.size; ++i)
    if (d.data[i] < -1 || d.data[i] > 1)
      throw py::value_error(std::string(name) + ": expected -1, 0 or +1, found " + std::to_string(int(d.data[i])) +
                            " at row " + std::to_string(i / cols) + ", column " + std::to_string(i % cols));
  return d;
}

py::array_t<double> new_array(std::vector<py::ssize_t> shape) { return py::array_t<double>(std::move(shape)); }

py::array_t<double> to_array(std::span<const double> values, std::size_t cols) {
  py::array_t<double> a =
      cols ? new_array({static_cast<py::ssize_t>(values.size() / cols), static_cast<py::ssize_t>(cols)})
           : new_array({static_cast<py::ssize_t>(values.size())});
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(double));
  return a;
}

py::array_t<double> to_array(const Vec3& v) { return to_array(std::span<const double>(v.data(), 3)); }

py::array_t<std::int8_t> to_int8_array(std::span<const std::int8_t> values, std::size_t cols) {
  py::array_t<std::int8_t> a(std::vector<py::ssize_t>{static_cast<py::ssize_t>(cols ? values.size() / cols : 0),
                                                      static_cast<py::ssize_t>(cols)});
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size());
  return a;
}

std::vector<double> configuration(const Machine& m, py::handle obj, const char* name) {
  return as_std_vector(obj, name, m.axes.size());
}

namespace {

PyObject* g_error = nullptr;
PyObject* g_input_error = nullptr;
PyObject* g_model_error = nullptr;

}  // namespace

namespace {
std::mutex g_long_calls_mutex;
int g_long_calls = 0;
struct sigaction g_previous_sigint {};

extern "C" void interrupt_long_call(int) { request_interrupt(); }
}  // namespace

LongCall::LongCall() {
  const std::lock_guard lock(g_long_calls_mutex);
  if (g_long_calls++ > 0) return;
  clear_interrupt();
  struct sigaction sa {};
  sa.sa_handler = interrupt_long_call;
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, &g_previous_sigint);
}

LongCall::~LongCall() {
  const std::lock_guard lock(g_long_calls_mutex);
  if (--g_long_calls > 0) return;
  ::sigaction(SIGINT, &g_previous_sigint, nullptr);
  clear_interrupt();
}

void register_exceptions(py::module_& m) {
  g_error = PyErr_NewExceptionWithDoc("mtcal.Error", "Base class of every exception mtcal raises on purpose.",
                                      PyExc_RuntimeError, nullptr);
  py::tuple input_bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
  g_input_error = PyErr_NewExceptionWithDoc(
      "mtcal.InputError",
      "Malformed or inconsistent input data (files, values). Attributes file, line (0: unknown) and field "
      "say where; the message says what was expected and what was found.",
      input_bases.ptr(), nullptr);
  py::tuple model_bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
  g_model_error = PyErr_NewExceptionWithDoc(
      "mtcal.ModelError", "A request the model cannot satisfy (unknown parameter name, axis not in the topology ...).",
      model_bases.ptr(), nullptr);
  m.attr("Error") = py::handle(g_error);
  m.attr("InputError") = py::handle(g_input_error);
  m.attr("ModelError") = py::handle(g_model_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Interrupted&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const InputError& e) {
      py::object exc = py::reinterpret_borrow<py::object>(g_input_error)(e.what());
      exc.attr("file") = e.where().file;
      exc.attr("line") = e.where().line;
      exc.attr("field") = e.where().field;
      PyErr_SetObject(g_input_error, exc.ptr());
    } catch (const ModelError& e) {
      PyErr_SetString(g_model_error, e.what());
    } catch (const Error& e) {
      PyErr_SetString(g_error, e.what());
    }
  });
}

}  // namespace mtcal::python

PYBIND11_MODULE(_mtcal, m) {
  using namespace mtcal::python;
  m.doc() = "mtcal's C++ library for Python (the compiled part of the package mtcal; import mtcal).";
  m.attr("__version__") = MTCAL_VERSION;
  register_exceptions(m);
  bind_model(m);
  bind_evaluation(m);
  bind_probing_identification(m);
  bind_prediction_compensation(m);
  bind_measurements(m);
  bind_history(m);
  bind_acceptance_reports(m);
  bind_planning(m);
  bind_rehearsal(m);
  // Every command's --precision: the digits of the numbers written to CSV files (process-wide, as in the command).
  m.def(
      "set_precision", [](int digits) { mtcal::set_significant_digits(digits); }, py::arg("digits"),
      "Significant digits of the numbers the writers put in CSV and parameter-table cells (the commands' "
      "--precision): 10 unless set, up to 17 (every double read back bit for bit). Process-wide. to_dict() is "
      "always exact.");
  m.def(
      "precision", [] { return mtcal::significant_digits(); },
      "The significant digits of written numbers (set_precision; 10 unless set).");
  // A private hook for the tests: the address of the buffer the functions read for an input,
  // to show that a C-contiguous float64 array is used in place.
  m.def(
      "_input_address",
      [](py::handle obj, std::size_t cols) {
        return reinterpret_cast<std::uintptr_t>(as_rows(obj, "configs", cols, false).data);
      },
      py::arg("array"), py::arg("cols"));
}
