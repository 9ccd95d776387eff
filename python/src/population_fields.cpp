// moreau.particles.Population and diffusing fields (particles/population_fields.h): the coupling
// from dicts named like the tool's keys, numpy views of the fields (read and write) and of the
// samples at the agents (read only).
#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/fields/field_set.h"
#include "moreau/particles/population.h"

namespace moreau::python {
namespace {

using particles::FieldCouplingOptions;
using particles::Population;
using particles::SubstrateResponse;

// A struct from a dict of its field list's keys (ValueError "KEY: REASON" as the tool says it);
// `addressed` names the keys set by `address` instead (a response's type and substrate).
template <typename T, typename Address>
T FromDict(const py::dict& d, const std::string& what, Address address) {
  T object;
  for (const auto& [key, value] : d) {
    const std::string name = py::str(key);
    if (address(object, name, value)) continue;
    if (T::Fields().Find(name) == nullptr) {
      throw InputError(what + "." + name, "unknown key");
    }
    try {
      T::Fields().Set(object, name, PythonToJson(value));
    } catch (const InputError& e) {
      throw e.Under(what);
    }
  }
  return object;
}

void CoupleFields(Population& p, double spacing, const std::vector<double>& lower,
                  const std::vector<double>& upper, const std::vector<py::dict>& substrates,
                  const std::vector<py::dict>& responses, const std::string& interpolation,
                  int substeps) {
  fields::Grid grid;
  grid.dimension = p.engine().dimension();
  grid.spacing = spacing;
  const auto k = static_cast<std::size_t>(grid.dimension);
  if (lower.size() != k || upper.size() != k) {
    throw InputError("lower", "lower and upper need one number per axis (the dimension)");
  }
  for (std::size_t a = 0; a < k; ++a) {
    grid.lower[a] = lower[a];
    grid.upper[a] = upper[a];
  }
  std::vector<fields::Substrate> subs;
  for (const py::dict& d : substrates) {
    subs.push_back(FromDict<fields::Substrate>(
        d, "substrates", [](fields::Substrate&, const std::string&, py::handle) { return false; }));
  }
  FieldCouplingOptions o;
  FieldCouplingOptions::Fields().Set(o, "interpolation", interpolation);
  FieldCouplingOptions::Fields().Set(o, "substeps", substeps);
  for (const py::dict& d : responses) {
    o.responses.push_back(FromDict<SubstrateResponse>(
        d, "responses", [](SubstrateResponse& r, const std::string& name, py::handle value) {
          if (name == "type") r.type = py::str(value);
          if (name == "substrate") r.substrate = py::str(value);
          return name == "type" || name == "substrate";
        }));
  }
  const int threads = p.engine().threads();
  p.CoupleFields(fields::FieldSet(grid, std::move(subs), threads), std::move(o));
}

fields::FieldSet& FieldsOf(Population& p) {
  fields::FieldSet* f = p.MutableFields();
  if (f == nullptr) throw InputError("fields", "none: call couple_fields first");
  return *f;
}

// A read-only (N,) or (N, k) view of a sample array owned by `self`.
py::array SampleView(py::object self, std::span<const double> values, py::ssize_t columns) {
  const auto n = static_cast<py::ssize_t>(values.size()) / columns;
  std::vector<py::ssize_t> shape = {n};
  if (columns > 1) shape.push_back(columns);
  py::array view(py::dtype::of<double>(), shape, {}, values.data(), self);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

}  // namespace

void BindPopulationFields(py::class_<Population>& c) {
  c.def(
       "couple_fields",
       [](Population& p, double spacing, const std::vector<double>& lower,
          const std::vector<double>& upper, const std::vector<py::dict>& substrates,
          const std::vector<py::dict>& responses, const std::string& interpolation,
          int substeps) {
         CoupleFields(p, spacing, lower, upper, substrates, responses, interpolation, substeps);
       },
       py::arg("spacing"), py::arg("lower"), py::arg("upper"), py::arg("substrates"),
       py::arg("responses") = std::vector<py::dict>{}, py::arg("interpolation") = "voxel",
       py::arg("substeps") = 1,
       "Couples the agents to diffusing fields on the grid [lower, upper] of voxel edge `spacing` "
       "(docs/fields.md \"Agents and fields\"): substrates are dicts of the keys of [fields.<name>] "
       "with 'name'; responses dicts with 'type', 'substrate' and the keys of "
       "types.<type>.<substrate>. Before the first step.")
      .def_property_readonly(
          "field_names",
          [](const Population& p) {
            std::vector<std::string> names;
            if (p.fields() != nullptr) {
              for (const fields::Substrate& s : p.fields()->substrates()) names.push_back(s.name);
            }
            return names;
          },
          "The substrates' names (empty without fields).")
      .def(
          "field",
          [](py::object self, const std::string& name) {
            fields::FieldSet& f = FieldsOf(self.cast<Population&>());
            const std::span<double> v = f.values(f.SubstrateIndex(name));
            const std::array<int, 3> n = f.grid().cells();
            std::vector<py::ssize_t> shape = {n[1], n[0]};
            if (f.grid().dimension == 3) shape.insert(shape.begin(), n[2]);
            return py::array(py::dtype::of<double>(), shape, {}, v.data(), self);
          },
          py::arg("name"),
          "Writable view of substrate `name`'s values, (n_y, n_x) or (n_z, n_y, n_x) (x "
          "fastest); what is written is the field the next step starts from.")
      .def(
          "field_values",
          [](py::object self, const std::string& name) {
            Population& p = self.cast<Population&>();
            return SampleView(self, p.FieldSamples(FieldsOf(p).SubstrateIndex(name)), 1);
          },
          py::arg("name"),
          "(N,) read-only view: substrate `name` sampled at every agent at the last rule step.")
      .def(
          "field_gradients",
          [](py::object self, const std::string& name) {
            Population& p = self.cast<Population&>();
            return SampleView(self, p.FieldGradients(FieldsOf(p).SubstrateIndex(name)),
                              p.engine().dimension());
          },
          py::arg("name"), "(N, k) read-only view: the gradient sampled at every agent.")
      .def_property_readonly(
          "field_time",
          [](const Population& p) { return p.fields() != nullptr ? p.fields()->time() : 0.0; },
          "The fields' time (the engine's at the last rule step).")
      .def(
          "field_total",
          [](Population& p, const std::string& name) {
            const fields::FieldSet& f = FieldsOf(p);
            return f.Total(f.SubstrateIndex(name));
          },
          py::arg("name"), "∫ c dV over the box.");
}

}  // namespace moreau::python
