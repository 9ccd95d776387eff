// The module moreau._moreau: errors, the shared helpers and the submodules.
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/common/hash.h"

namespace moreau::python {

py::object JsonToPython(const nlohmann::json& j) {
  // Kept for the life of the process (released, never decremented after finalisation).
  static const py::handle loads = py::object(py::module_::import("json").attr("loads")).release();
  return loads(j.dump());
}

nlohmann::json PythonToJson(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json j = nlohmann::json::array();
    for (const py::handle item : value) j.push_back(PythonToJson(item));
    return j;
  }
  if (py::isinstance<py::int_>(value) || py::hasattr(value, "__index__")) {
    return py::int_(py::reinterpret_borrow<py::object>(value)).cast<std::int64_t>();
  }
  if (py::isinstance<py::float_>(value) || py::hasattr(value, "__float__")) {
    return py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>();
  }
  throw py::type_error("expected a number, a boolean, a string or a list of them, got " +
                       std::string(py::str(py::type::of(value).attr("__name__"))));
}

void SetOptions(py::object self, const py::kwargs& kwargs) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    if (name.empty() || name[0] == '_' || !py::hasattr(self, name.c_str())) {
      throw InputError(std::string(py::str(py::type::of(self).attr("__name__"))) +
                       ": unknown option '" + name + "'");
    }
    py::setattr(self, name.c_str(), value);
  }
}

namespace {
py::handle numerical_error_type;  // moreau.NumericalError, set when the module loads
}  // namespace

void RaiseNumericalError(const std::string& message, const py::dict& attributes) {
  py::object error = numerical_error_type(message);
  for (const auto& [key, value] : attributes) py::setattr(error, key, value);
  PyErr_SetObject(numerical_error_type.ptr(), error.ptr());
  throw py::error_already_set();
}

}  // namespace moreau::python

PYBIND11_MODULE(_moreau, m) {
  namespace py = pybind11;
  using namespace moreau::python;
  m.doc() =
      "moreau: constrained particle motion (PBD), optimal control of spring networks and "
      "motion-capture gap filling (docs/python.md).";

  // InputError → ValueError with the same message; NumericalError → moreau.NumericalError.
  // The type lives as long as the process: a handle, never decremented at exit.
  numerical_error_type =
      py::exception<moreau::NumericalError>(m, "NumericalError", PyExc_RuntimeError).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const moreau::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const moreau::NumericalError& e) {
      PyErr_SetString(numerical_error_type.ptr(), e.what());
    }
  });

  m.def(
      "hash_doubles",
      [](const py::array_t<double, py::array::c_style | py::array::forcecast>& values) {
        return moreau::HashDoublesHex({values.data(), static_cast<std::size_t>(values.size())});
      },
      py::arg("values"),
      "FNV-1a of the bytes of the values in C order, 16 hex digits: the positions_hash of "
      "summary.json for the final positions (id order).");

  py::module_ particles = m.def_submodule("particles", "The particle engine at scale.");
  RegisterParticles(particles);
  RegisterPopulation(particles);
  py::module_ pbd = m.def_submodule("pbd", "The paper's methods: sets, steppers, cases, studies.");
  RegisterPbd(pbd);
  py::module_ control = m.def_submodule("control", "Optimal control of spring networks.");
  RegisterControl(control);
  py::module_ mocap = m.def_submodule("mocap", "Motion-capture recordings and gap filling.");
  RegisterMocap(mocap);
}
