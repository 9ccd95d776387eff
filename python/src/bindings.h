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
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <nlohmann/json.hpp>

#include "moreau/common/error.h"

namespace moreau::python {

namespace py = pybind11;

void RegisterParticles(py::module_& m);
void RegisterPopulation(py::module_& m);  // in moreau.particles, after RegisterParticles
// The crowd types of moreau.particles (crowds.cpp), registered by RegisterParticles before the
// forces that hold them.
void BindCrowdTypes(py::module_& m);
void RegisterPbd(py::module_& m);
void RegisterControl(py::module_& m);
void RegisterMocap(py::module_& m);

// JSON → Python objects (dict, list, float, int, str, None) through the json module.
py::object JsonToPython(const nlohmann::json& j);

// Python → JSON (bool, int, float, str, lists and tuples of them; numpy scalars through
// __index__ / __float__); TypeError for anything else.
nlohmann::json PythonToJson(const py::handle& value);

// Sets the attributes named by the keyword arguments on `self` (an object without a field list:
// a model, a case). An unknown name raises ValueError "TYPE: unknown option 'NAME'".
void SetOptions(py::object self, const py::kwargs& kwargs);

// The type has a field list (field_list.h): its keys, ranges and help are those of the tool.
template <typename T>
concept HasFieldList = requires {
  T::Fields();
};

// Sets `object`'s fields from keyword arguments: a key of T::Fields() (dotted keys through
// **{"newton.armijo": 0.1}) is set and checked by the list (ValueError "KEY: REASON", the
// tool's reason); another name must be an attribute (a nested options object).
template <typename T>
void SetFields(T& object, const py::kwargs& kwargs) {
  if constexpr (HasFieldList<T>) {
    py::kwargs rest;
    for (const auto& [key, value] : kwargs) {
      const std::string name = py::str(key);
      if (T::Fields().Find(name) != nullptr) {
        T::Fields().Set(object, name, PythonToJson(value));
      } else {
        rest[key] = value;
      }
    }
    SetOptions(py::cast(&object, py::return_value_policy::reference), rest);
  } else {
    SetOptions(py::cast(&object, py::return_value_policy::reference), kwargs);
  }
}

// A new T (an options struct, a model, a case) from keyword arguments named like its fields, then
// its field list's checks (or T::Validate() for a type without a list): `T(**kwargs)`.
template <typename T>
std::unique_ptr<T> FromKwargs(const py::kwargs& kwargs) {
  auto object = std::make_unique<T>();
  SetFields(*object, kwargs);
  if constexpr (HasFieldList<T>) {
    T::Fields().Validate(*object);  // the fields; validate() checks the whole (e.g. the types)
  } else if constexpr (requires(const T& t) { t.Validate(); }) {
    object->Validate();
  }
  return object;
}

// `base` (or the defaults) with the keyword arguments set: the `options=None, **kwargs` of the
// functions that run something. Validation is left to the C++ function called.
template <typename T>
T WithKwargs(const std::optional<T>& base, const py::kwargs& kwargs) {
  T object = base.value_or(T{});
  SetFields(object, kwargs);
  return object;
}

// "Keyword arguments (the tool's keys):" and one line per key of the list: type, default, range,
// unit, help. The docstring of an options class.
template <typename T>
std::string FieldsDoc(const std::string& summary) {
  std::string doc = summary +
                    "\n\nKeyword arguments and attributes (the tool's keys; dotted ones "
                    "through set()):\n";
  const T defaults{};
  for (const auto& f : T::Fields().fields()) {
    doc += "  " + f.key + " (" + f.type + (f.range.empty() ? "" : ", " + f.range) +
           (f.unit.empty() ? "" : ", " + f.unit) + "; default " + f.get(defaults).dump() +
           "): " + f.help + "\n";
  }
  return doc;
}

// An options class from its field list: T(**kwargs) (validated), a property per undotted key
// (read and written as the tool reads them, checked on assignment), set(key, value) and
// get(key) for every key, keys(), validate() and to_dict(). Returns the class for additions
// (nested options objects as attributes).
template <typename T>
py::class_<T> BindOptionsClass(py::handle scope, const char* name, const std::string& summary) {
  py::class_<T> c(scope, name, FieldsDoc<T>(summary).c_str());
  c.def(py::init(&FromKwargs<T>));
  for (const auto& f : T::Fields().fields()) {
    if (f.key.find('.') != std::string::npos) continue;
    c.def_property(
        f.key.c_str(), [get = f.get](const T& o) { return JsonToPython(get(o)); },
        [key = f.key](T& o, const py::object& v) { T::Fields().Set(o, key, PythonToJson(v)); },
        f.help.c_str());
  }
  c.def(
       "set",
       [](T& o, const std::string& key, const py::object& v) {
         T::Fields().Set(o, key, PythonToJson(v));
       },
       py::arg("key"), py::arg("value"), "Sets a key (dotted for nested options), checked.")
      .def(
          "get",
          [](const T& o, const std::string& key) {
            const auto* f = T::Fields().Find(key);
            if (f == nullptr) throw InputError(key, "unknown key");
            return JsonToPython(f->get(o));
          },
          py::arg("key"), "The value of a key (dotted for nested options).")
      .def_static(
          "keys",
          [] {
            std::vector<std::string> keys;
            for (const auto& f : T::Fields().fields()) keys.push_back(f.key);
            return keys;
          },
          "Every key, as the tool names it below its table.")
      .def_static(
          "fields",
          [] {
            py::list out;
            const T defaults{};
            for (const auto& f : T::Fields().fields()) {
              py::dict d;
              d["key"] = f.key;
              d["type"] = f.type;
              d["range"] = f.range;
              d["unit"] = f.unit;
              d["help"] = f.help;
              d["default"] = JsonToPython(f.get(defaults));
              out.append(d);
            }
            return out;
          },
          "Every field: key, type, range, unit, help and default.")
      .def("validate",
           [](const T& o) {
             if constexpr (requires { o.Validate(); }) {
               o.Validate();
             } else {
               T::Fields().Validate(o);
             }
           })
      .def("to_dict", [](const T& o) { return JsonToPython(T::Fields().ToJson(o)); })
      .def("__repr__", [name](const T& o) {
        return std::string(name) + "(" + T::Fields().ToJson(o).dump() + ")";
      });
  return c;
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
