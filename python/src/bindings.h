// Shared helpers of the Python bindings (module moreau._moreau): options from keyword arguments,
// summaries as objects with attributes and to_dict(), and the run guard that releases the GIL
// and checks for Ctrl-C between steps.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

namespace moreau::python {

namespace py = pybind11;

void RegisterParticles(py::module_& m);
void RegisterPbd(py::module_& m);
void RegisterControl(py::module_& m);
void RegisterMocap(py::module_& m);

// JSON → Python objects (dict, list, float, int, str, None) through the json module.
py::object JsonToPython(const nlohmann::json& j);

// Sets the attributes named by the keyword arguments on `self` (an options object). An unknown
// name raises ValueError "TYPE: unknown option 'NAME'"; a value of the wrong type TypeError.
void SetOptions(py::object self, const py::kwargs& kwargs);

// A new T (an options struct, a model, a case) from keyword arguments named like its fields, then
// T::Validate() when T has one: the constructor `T(**kwargs)` of every options type.
template <typename T>
std::unique_ptr<T> FromKwargs(const py::kwargs& kwargs) {
  auto object = std::make_unique<T>();
  SetOptions(py::cast(object.get(), py::return_value_policy::reference), kwargs);
  if constexpr (requires(const T& t) { t.Validate(); }) object->Validate();
  return object;
}

// `base` (or the defaults) with the keyword arguments set: the `options=None, **kwargs` of the
// functions that run something. Validation is left to the C++ function called.
template <typename T>
T WithKwargs(const std::optional<T>& base, const py::kwargs& kwargs) {
  T object = base.value_or(T{});
  SetOptions(py::cast(&object, py::return_value_policy::reference), kwargs);
  return object;
}

// Raises moreau.NumericalError(message) with the given attributes (summary, state, …).
[[noreturn]] void RaiseNumericalError(const std::string& message, const py::dict& attributes);

// Thrown from a C++ observer when PyErr_CheckSignals found a pending KeyboardInterrupt (or a
// Python observer raised): the Python error is set on this thread; the binding rethrows it once
// it holds the GIL again.
struct PythonErrorPending {};

// Called from C++ loops (with the GIL released) after every step. It takes the GIL when `call`
// is true (then it also calls python_call) or when `interval` has passed since it last took it,
// and checks for signals (Ctrl-C). Throws PythonErrorPending. Taking the GIL at most every 10 ms
// when there is nothing to call keeps the loop free of waits for other Python threads.
class InterruptCheck {
 public:
  using Clock = std::chrono::steady_clock;
  explicit InterruptCheck(Clock::duration interval = std::chrono::milliseconds(10))
      : interval_(interval), last_(Clock::now()) {}
  template <typename Call>
  void Tick(bool call, Call&& python_call) {
    const Clock::time_point now = Clock::now();
    if (!call && now - last_ < interval_) return;
    last_ = now;
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw PythonErrorPending{};
    if (!call) return;
    try {
      std::forward<Call>(python_call)();
    } catch (py::error_already_set& e) {
      e.restore();
      throw PythonErrorPending{};
    }
  }

 private:
  Clock::duration interval_;
  Clock::time_point last_;
};

// Binds a summary type: to_dict() (its ToJson()), ok, termination, message, attribute access to
// every key of to_dict() and a one-line repr.
template <typename Summary, typename... Extra>
py::class_<Summary> BindSummary(py::handle scope, const char* name, const char* doc) {
  py::class_<Summary> c(scope, name, doc);
  c.def(
       "to_dict", [](const Summary& s) { return JsonToPython(s.ToJson()); },
       "The summary as a dict (the same keys as summary.json).")
      .def_property_readonly("ok", &Summary::ok)
      .def_readonly("message", &Summary::message)
      .def("__getattr__",
           [](const Summary& s, const std::string& key) -> py::object {
             const nlohmann::json j = s.ToJson();
             if (!j.contains(key)) throw py::attribute_error(key);
             return JsonToPython(j.at(key));
           })
      .def("__repr__", [name](const Summary& s) {
        const nlohmann::json j = s.ToJson();
        return std::string(name) + "(termination=" + j.value("termination", "") + ", message='" +
               s.message + "')";
      });
  return c;
}

}  // namespace moreau::python
