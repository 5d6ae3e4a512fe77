// The Python module `shearbench`: the public C++ API (include/shearbench/sensor_model.hpp) with NumPy arrays.
// Arrays pass without a copy when they are float64 and C-contiguous (a pose array [envs, 7], an `out` field
// [envs, markers, 2]); another dtype or layout of an input is converted once. The GIL is released during a
// step (the envs run on TBB's threads). shearbench.Error (a ValueError) carries the CLI's message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <shearbench/sensor_model.hpp>
#include <span>
#include <string>

namespace py = pybind11;

namespace {

using InArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using OutArray = py::array_t<double, py::array::c_style>;

// The poses as a [n, 7] view; n must be the model's envs.
std::span<const double> poses_of(const InArray& a, const shearbench::SensorModel& m, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != shearbench::kPoseValues || a.shape(0) != m.envs())
    throw shearbench::Error(std::string(name) + ": expected shape (" + std::to_string(m.envs()) +
                            ", 7) (x y z qw qx qy qz per env)");
  return {a.data(), static_cast<std::size_t>(a.size())};
}

// `out` when given (checked: float64, C-contiguous, writeable, [envs, markers, 2]), else a new array.
OutArray field_array(const std::optional<py::array>& out, const shearbench::SensorModel& m) {
  const std::vector<py::ssize_t> shape = {m.envs(), m.markers(), 2};
  if (!out) return OutArray(shape);
  const py::array& a = *out;
  const bool ok = a.dtype().is(py::dtype::of<double>()) && (a.flags() & py::array::c_style) && a.writeable() &&
                  a.ndim() == 3 && a.shape(0) == shape[0] && a.shape(1) == shape[1] && a.shape(2) == 2;
  if (!ok)
    throw shearbench::Error("out: expected a writeable C-contiguous float64 array of shape (" +
                            std::to_string(m.envs()) + ", " + std::to_string(m.markers()) + ", 2)");
  return py::reinterpret_borrow<OutArray>(a);
}

py::array_t<std::uint8_t> contact_array(bool wanted, const shearbench::SensorModel& m) {
  return wanted ? py::array_t<std::uint8_t>(std::vector<py::ssize_t>{m.envs(), m.markers()})
                : py::array_t<std::uint8_t>(std::vector<py::ssize_t>{0});
}

py::object step_result(const OutArray& field, const py::array_t<std::uint8_t>& contact, bool wanted) {
  if (!wanted) return field;
  return py::make_tuple(field, contact);
}

}  // namespace

PYBIND11_MODULE(shearbench, m) {
  m.doc() =
      "Batched tactile shear models (HydroShear, FOTS, TacSL and HydroShear's corrected forms): E sensor "
      "poses in, E x markers x 2 marker displacements (pixels) out. See docs/library.md.";
  py::register_exception<shearbench::Error>(m, "Error", PyExc_ValueError);

  py::class_<shearbench::SensorModel>(m, "SensorModel", R"(A batch of `envs` sensors of one model.

model: a model form or "<form>+<effect>+..." (model_names(), effect_names()).
param_set: a shipped set's name or a set file ("" : the sensor's default set; "published": the authors').
params_file: a params file on top, e.g. a residual loop's report_params.json (see loop_answer()).
scene: a scene file (scenes/*.json) giving the sensor, the indenter and its params table.
sensor, indenter: a scene's "sensor" / "indenter" block as JSON text; indenter "bench_peg" is the benchmark's peg.)")
      .def(py::init([](const std::string& model, const std::string& param_set, const std::string& params_file,
                       const std::string& scene, const std::string& sensor, const std::string& indenter, int envs,
                       const std::string& data_root) {
             shearbench::Config c;
             c.model = model;
             c.param_set = param_set;
             c.params_file = params_file;
             c.scene = scene;
             c.sensor = sensor;
             c.indenter = indenter;
             c.envs = envs;
             c.data_root = data_root;
             return shearbench::SensorModel::create(c);
           }),
           py::arg("model") = "hydroshear", py::kw_only(), py::arg("param_set") = "", py::arg("params_file") = "",
           py::arg("scene") = "", py::arg("sensor") = "", py::arg("indenter") = "", py::arg("envs") = 1,
           py::arg("data_root") = "")
      .def_property_readonly("model", &shearbench::SensorModel::model)
      .def_property_readonly("envs", &shearbench::SensorModel::envs)
      .def_property_readonly("markers", &shearbench::SensorModel::markers)
      .def_property_readonly("markers_rest_px",
                             [](const shearbench::SensorModel& s) {
                               const std::vector<double> v = s.markers_rest_px();
                               OutArray a(std::vector<py::ssize_t>{s.markers(), 2});
                               std::copy(v.begin(), v.end(), a.mutable_data());
                               return a;
                             })
      .def_property_readonly("mm_per_px", &shearbench::SensorModel::mm_per_px)
      .def("params_json", &shearbench::SensorModel::params_json, "the parameter values, as JSON text")
      .def(
          "step",
          [](shearbench::SensorModel& s, const InArray& X_EI, double dt, std::optional<py::array> out, bool contact) {
            const std::span<const double> poses = poses_of(X_EI, s, "X_EI");
            OutArray field = field_array(out, s);
            py::array_t<std::uint8_t> flags = contact_array(contact, s);
            std::span<double> f(field.mutable_data(), static_cast<std::size_t>(field.size()));
            std::span<std::uint8_t> c(flags.mutable_data(), static_cast<std::size_t>(flags.size()));
            {
              py::gil_scoped_release unlocked;
              s.step(poses, dt, f, c);
            }
            return step_result(field, flags, contact);
          },
          py::arg("X_EI"), py::arg("dt"), py::arg("out") = py::none(), py::arg("contact") = false,
          R"(One step of every env to X_EI [envs, 7] (x y z qw qx qy qz, the indenter in the gel's frame E) after
dt seconds. Returns the field [envs, markers, 2] in pixels (written into `out` when given), and with
contact=True also the in-contact flags [envs, markers].)")
      .def(
          "step_world",
          [](shearbench::SensorModel& s, const InArray& X_WE, const InArray& X_WI, double dt,
             std::optional<py::array> out, bool contact) {
            const std::span<const double> we = poses_of(X_WE, s, "X_WE"), wi = poses_of(X_WI, s, "X_WI");
            OutArray field = field_array(out, s);
            py::array_t<std::uint8_t> flags = contact_array(contact, s);
            std::span<double> f(field.mutable_data(), static_cast<std::size_t>(field.size()));
            std::span<std::uint8_t> c(flags.mutable_data(), static_cast<std::size_t>(flags.size()));
            {
              py::gil_scoped_release unlocked;
              s.step_world(we, wi, dt, f, c);
            }
            return step_result(field, flags, contact);
          },
          py::arg("X_WE"), py::arg("X_WI"), py::arg("dt"), py::arg("out") = py::none(), py::arg("contact") = false,
          "step() from world poses of the gel (X_WE) and the indenter (X_WI), [envs, 7] each")
      .def("reset", py::overload_cast<>(&shearbench::SensorModel::reset), "every env back to rest")
      .def("reset", py::overload_cast<int>(&shearbench::SensorModel::reset), py::arg("env"), "one env back to rest");

  m.def("model_names", &shearbench::model_names, "the model forms");
  m.def("effect_names", &shearbench::effect_names, "the effects a form may carry (\"<form>+<effect>\")");
  m.def("param_set_names", &shearbench::param_set_names, "the shipped parameter sets");
  m.def(
      "loop_answer",
      [](const std::string& run) {
        const shearbench::Config c = shearbench::loop_answer(run);
        py::dict d;
        d["model"] = c.model;
        d["params_file"] = c.params_file;
        return d;
      },
      py::arg("run"),
      "a residual run's answer (docs/residuals/<run>): {'model': ..., 'params_file': ...}, keyword arguments "
      "for SensorModel");
  m.def(
      "bench_poses",
      [](int envs, int steps) {
        const std::vector<double> v = shearbench::bench_poses(envs, steps);
        OutArray a(std::vector<py::ssize_t>{steps, 2 * static_cast<py::ssize_t>(envs), shearbench::kPoseValues});
        std::copy(v.begin(), v.end(), a.mutable_data());
        return a;
      },
      py::arg("envs"), py::arg("steps") = 23,
      "the benchmark workload's poses [steps, envs * 2, 7] (env * 2 + pad): the peg in each pad's frame");
  m.attr("bench_dt") = shearbench::bench_dt();
  m.attr("__version__") = shearbench::version();
}
