// moreau.mocap: recordings (read, write, arrays), gaps, fills and the evaluation protocol.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.h"
#include "moreau/common/error.h"
#include "moreau/mocap/evaluate.h"
#include "moreau/mocap/fill.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"
#include "moreau/mocap/recording_io.h"

namespace moreau::python {
namespace {

using namespace moreau::mocap;

// A recording from an (F, M, 3) array; NaN samples are missing.
Recording FromArray(std::vector<std::string> labels,
                    const py::array_t<double, py::array::c_style | py::array::forcecast>& x,
                    double rate, const std::string& units) {
  const auto markers = static_cast<py::ssize_t>(labels.size());
  if (x.ndim() != 3 || x.shape(1) != markers || x.shape(2) != 3) {
    throw InputError("positions must have shape (frames, " + std::to_string(markers) + ", 3)");
  }
  Recording r(std::move(labels), x.shape(0), rate, units);
  const auto a = x.unchecked<3>();
  for (py::ssize_t f = 0; f < x.shape(0); ++f) {
    for (py::ssize_t m = 0; m < markers; ++m) {
      const Eigen::Vector3d p(a(f, m, 0), a(f, m, 1), a(f, m, 2));
      if (p.allFinite()) r.SetPoint(f, static_cast<int>(m), p);
    }
  }
  return r;
}

// What the points are: their descriptions, types and the types' units.
void BindPointDetails(py::class_<Recording>& recording) {
  recording
      .def_property_readonly(
          "descriptions", [](const Recording& r) { return r.descriptions(); },
          "The description of every point (C3D POINT:DESCRIPTIONS; may be empty).")
      .def_property_readonly(
          "point_types",
          [](const Recording& r) {
            std::vector<std::string> out;
            for (PointType type : r.types()) out.emplace_back(ToString(type));
            return out;
          },
          "The type of every point: 'marker', or a model output 'angle', 'force', 'moment', "
          "'power', 'scalar', 'reaction' (C3D POINT:ANGLES, FORCES, …); only markers are "
          "filled.")
      .def_property_readonly(
          "type_units",
          [](const Recording& r) {
            std::map<std::string, std::string> out;
            for (PointType type : AllPointTypes()) {
              if (type != PointType::kMarker && !r.type_units(type).empty()) {
                out.emplace(ToString(type), r.type_units(type));
              }
            }
            return out;
          },
          "The units of the model-output types that the file states, e.g. {'angle': 'deg'}.");
}

void BindRecording(py::module_& m) {
  py::class_<Recording> recording(m, "Recording",
                                  "M labelled markers at F frames, with holes (NaN).");
  recording
      .def(py::init(&FromArray), py::arg("labels"), py::arg("positions"), py::arg("rate"),
           py::arg("units") = "mm", "From an (F, M, 3) array; NaN marks a missing sample.")
      .def_property_readonly("markers", &Recording::markers)
      .def_property_readonly("frames", &Recording::frames)
      .def_property_readonly("rate", &Recording::rate)
      .def_property_readonly("units", &Recording::units)
      .def_property_readonly("labels", &Recording::labels)
      .def_property_readonly("first_frame", &Recording::first_frame)
      .def_property_readonly(
          "positions",
          [](py::object self) {
            const Recording& r = self.cast<const Recording&>();
            py::array view(py::dtype::of<double>(),
                           {r.frames(), py::ssize_t{r.markers()}, py::ssize_t{3}}, {},
                           r.positions().data(), self);
            view.attr("setflags")(py::arg("write") = false);
            return view;
          },
          "(F, M, 3) read-only view of the positions (NaN where missing), no copy.")
      .def_property_readonly(
          "observed",
          [](const Recording& r) {
            py::array_t<bool> out({r.frames(), py::ssize_t{r.markers()}});
            auto o = out.mutable_unchecked<2>();
            for (std::int64_t f = 0; f < r.frames(); ++f) {
              for (int k = 0; k < r.markers(); ++k) o(f, k) = r.observed(f, k);
            }
            return out;
          },
          "(F, M) bool: a copy (the mask is stored as bytes).")
      .def("find_marker", &Recording::FindMarker, py::arg("label"))
      .def("convert_units", &Recording::ConvertUnits, py::arg("units"));
  BindPointDetails(recording);
  py::class_<Gap>(m, "Gap", "A run of missing frames [first, last] of one marker.")
      .def(py::init([](int marker, std::int64_t first, std::int64_t last) {
             return Gap{marker, first, last};
           }),
           py::arg("marker"), py::arg("first"), py::arg("last"))
      .def_readwrite("marker", &Gap::marker)
      .def_readwrite("first", &Gap::first)
      .def_readwrite("last", &Gap::last)
      .def_property_readonly("length", &Gap::length)
      .def("__repr__", [](const Gap& g) {
        return "Gap(marker=" + std::to_string(g.marker) + ", first=" + std::to_string(g.first) +
               ", last=" + std::to_string(g.last) + ")";
      });
  m.def("find_gaps", &FindGaps, py::arg("recording"));
  m.def(
      "read_recording",
      [](const std::filesystem::path& path, const py::kwargs& kw) {
        const ReadOptions options = WithKwargs(std::optional<ReadOptions>(), kw);
        options.Validate();
        std::vector<std::string> warnings;
        const py::gil_scoped_release release;
        Recording r = ReadRecording(path, options, &warnings);
        return std::make_pair(std::move(r), warnings);
      },
      py::arg("path"),
      "(recording, warnings) from a .c3d, .trc or .csv file. Keyword arguments are ReadOptions "
      "fields (zero_is_missing, allow_truncated, units, units_if_unstated, rate_if_unstated).");
  BindOptionsClass<ReadOptions>(m, "ReadOptions", "Keys of read.*: how a recording is read.");
  m.def(
      "write_recording",
      [](const Recording& r, const std::filesystem::path& path) {
        const py::gil_scoped_release release;
        WriteRecording(r, path);
      },
      py::arg("recording"), py::arg("path"), "Writes .c3d, .trc or .csv (by extension).");
}

// A field of GapFillOptions::baseline as an attribute of Python's FillOptions.
template <typename T>
void BindBaselineField(py::class_<GapFillOptions>& c, const char* name, T FillOptions::*field) {
  c.def_property(
      name, [field](GapFillOptions& o) -> T& { return o.baseline.*field; },
      [field](GapFillOptions& o, const T& value) { o.baseline.*field = value; });
}

void BindFillOptions(py::module_& m) {
  BindOptionsClass<InterpolationFillOptions>(m, "InterpolationFillOptions",
                                             "Keys of interpolation.* (spline, pchip).");
  BindOptionsClass<RigidFillOptions>(m, "RigidFillOptions", "Keys of rigid.*.");
  BindOptionsClass<PcaFillOptions>(m, "PcaFillOptions", "Keys of pca.*.");
  BindOptionsClass<MarkerNetworkOptions>(m, "MarkerNetworkOptions",
                                         "Keys of ocp.network.*: the network from a recording.")
      .def_readwrite("springs", &MarkerNetworkOptions::springs);
  BindOptionsClass<OcpFillOptions>(m, "OcpFillOptions", "Keys of ocp.*: the optimal-control fill.")
      .def_readwrite("network", &OcpFillOptions::network)
      .def_readwrite("newton", &OcpFillOptions::newton);
  // Python's FillOptions are the settings of a fill by any method (gap_fill.h): the method (ocp
  // included), the baseline fills' blocks and ocp.
  auto fill =
      BindOptionsClass<GapFillOptions>(m, "FillOptions",
                                       "Keys of fill-gaps: fill.method, fill.max_gap_seconds, "
                                       "interpolation.*, rigid.*, pca.*, ocp.*.");
  BindBaselineField(fill, "interpolation", &FillOptions::interpolation);
  BindBaselineField(fill, "rigid", &FillOptions::rigid);
  BindBaselineField(fill, "pca", &FillOptions::pca);
  fill.def_readwrite("ocp", &GapFillOptions::ocp);
  BindSummary<FillSummary>(m, "FillSummary", "The gaps filled and why the others were not.");
}

void BindFillAndEvaluate(py::module_& m) {
  m.def(
      "fill_gaps",
      [](const Recording& in, std::optional<std::vector<Gap>> gaps,
         std::optional<GapFillOptions> options, const py::kwargs& kw) {
        GapFillOptions o = WithKwargs(options, kw);
        Recording out;
        FillSummary summary;
        {
          const py::gil_scoped_release release;
          summary = FillGaps(in, gaps ? *gaps : FindGaps(in), o, &out);
        }
        return std::make_pair(std::move(out), summary);
      },
      py::arg("recording"), py::arg("gaps") = py::none(), py::arg("options") = py::none(),
      "(filled copy, FillSummary); gaps default to find_gaps(recording). Keyword arguments are "
      "FillOptions fields (method=\"spline\", max_gap_seconds=…).");
  BindOptionsClass<EvaluationOptions>(m, "EvaluationOptions", "Keys of evaluation.*.")
      .def_readwrite("fill", &EvaluationOptions::fill);
  BindSummary<EvaluationSummary>(m, "EvaluationSummary", "Errors per method and gap length.");
  m.def(
      "evaluate",
      [](const Recording& truth, std::optional<EvaluationOptions> options, const py::kwargs& kw) {
        EvaluationOptions o = WithKwargs(options, kw);
        const py::gil_scoped_release release;
        return EvaluateFillMethods(truth, o);
      },
      py::arg("truth"), py::arg("options") = py::none(),
      "Hides gaps in a complete recording, fills them with every method and measures the error. "
      "Keyword arguments are EvaluationOptions fields.");
}

}  // namespace

void RegisterMocap(py::module_& m) {
  BindRecording(m);
  BindFillOptions(m);
  BindFillAndEvaluate(m);
}

}  // namespace moreau::python
