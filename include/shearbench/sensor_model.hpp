#pragma once
// shearbench's public C++ API: a batched tactile sensor model for a training loop. Only the standard
// library is included here, so a consumer needs none of shearbench's build dependencies (find_package(shearbench
// CONFIG), target shearbench::shearbench; docs/library.md).
//
// Frames and units follow tsd/1: E is the elastomer frame (origin at the centre of the gel surface, +z out of
// the gel), I the indenter's body frame, W the world. A pose is 7 doubles, x y z (metres) then the unit
// quaternion qw qx qy qz: X_EI is the indenter in E. A field is du dv per marker in image pixels, relative to
// the marker's rest position (markers_rest_px()).
//
// Buffers are row-major and contiguous: poses [env][7], fields [env][marker][2]. The API never keeps a
// pointer to a caller's buffer beyond the call: inputs are read and outputs written during the call only, so
// a NumPy array or a std::vector passes without a copy.
//
// Threading. One SensorModel is not safe to call from two threads at once; distinct instances share nothing
// mutable and may be stepped concurrently. A step runs its envs in parallel on TBB's worker threads (it
// honours a tbb::global_control or task_arena of the caller).
//
// Errors: every function throws shearbench::Error (a std::runtime_error) with the message the shearbench CLI
// prints for the same input (the CLI names its flag, --model, where this names the field, model), e.g.
// "model: unknown model id 'x' (known: hydroshear, ...)" or "X_EI[env 3]: a pose value is not finite".
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

// What libshearbench.so exports (its version script, lib/shearbench.map, keeps everything else local).
#define SHEARBENCH_API __attribute__((visibility("default")))

namespace shearbench {

class SHEARBENCH_API Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what);
  ~Error() override;
};

// Values per pose: x y z qw qx qy qz.
inline constexpr int kPoseValues = 7;

struct Config {
  // A model by name: a published model or one of HydroShear's forms (model_names()), optionally followed by
  // effects, "<form>+<effect>+...", e.g. the residual loop's answer "hydroshear-contact+tool_frame".
  std::string model = "hydroshear";
  // The parameter set the model starts from: a shipped set's name (param_set_names(): "twin_sphere35",
  // "published" for the authors' values, ...) or a set file's path. Empty: the default set for the sensor.
  std::string param_set;
  // Optional: a params file on top of the set ({"<model>": {name: value}} or a flat table), e.g. a residual
  // loop's report_params.json (see loop_answer()).
  std::string params_file;
  // Optional: a scene file (scenes/*.json with a "trajectory"): its sensor, indenter and "params" table are
  // used (sensor and indenter below must then be empty). Relative paths resolve against the working folder.
  std::string scene;
  // The sensor, as a scene's "sensor" block in JSON ({"gel": "flat", "markers": "7x9", "camera": {...}}).
  // Empty: the GelSight Mini (63 markers, 0.0634 mm/px).
  std::string sensor;
  // The indenter, as a scene's "indenter" block in JSON ({"shape": "sphere", "radius_m": 0.004}), or
  // "bench_peg": the benchmark workload's capped-cylinder peg (R 4 mm, L 40 mm, its 1992 surface points).
  // Empty: a sphere of radius 4 mm.
  std::string indenter;
  // Independent sensors stepped together (e.g. 1024 environments x 2 pads = 2048). >= 1.
  int envs = 1;
  // "data:" paths in the scene or the blocks above resolve through this data root (empty: $SHEARBENCH_DATA,
  // else the checkout's ../shared/data).
  std::string data_root;
};

class SHEARBENCH_API SensorModel {
 public:
  // Builds the model, its parameters and every env's state (at rest). Throws Error on a bad config.
  static SensorModel create(const Config& config);
  ~SensorModel();
  SensorModel(SensorModel&&) noexcept;
  SensorModel& operator=(SensorModel&&) noexcept;
  SensorModel(const SensorModel&) = delete;
  SensorModel& operator=(const SensorModel&) = delete;

  // The model's name as given in the config, the envs, and the markers per env (M).
  const std::string& model() const;
  int envs() const;
  int markers() const;
  // Rest positions of the markers in pixels, [marker][2] (u, v).
  std::vector<double> markers_rest_px() const;
  // Millimetres per pixel of the sensor's orthographic camera (a field in mm is the field in px times this).
  // Throws Error for a pinhole camera, where the scale varies across the image.
  double mm_per_px() const;
  // The parameter values the model runs with, as "name": value JSON text (for logs and checks).
  std::string params_json() const;

  // One step of every env to its pose after dt seconds (> 0; the path-dependent models carry their state).
  // X_EI: envs() * 7 values; disp_px: envs() * markers() * 2 values, overwritten. in_contact, when not empty:
  // envs() * markers() flags, 1 where the marker lies in the contact patch (for the models that track it;
  // others write 0). Throws Error for a wrong size, a non-finite value or a zero quaternion (naming the env);
  // the state is then unchanged.
  void step(std::span<const double> X_EI, double dt, std::span<double> disp_px,
            std::span<std::uint8_t> in_contact = {});
  // The same from world poses: X_WE (the gel's frame) and X_WI (the indenter), envs() * 7 values each;
  // X_EI = X_WE^-1 X_WI.
  void step_world(std::span<const double> X_WE, std::span<const double> X_WI, double dt, std::span<double> disp_px,
                  std::span<std::uint8_t> in_contact = {});
  // Every env back to rest (out of contact, no history), or one env (0 <= env < envs()).
  void reset();
  void reset(int env);

  struct Impl;
  // For shearbench's own programs (the CLI, the bench): the implementation behind the API.
  Impl& impl() { return *impl_; }

 private:
  explicit SensorModel(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
  friend struct Impl;
};

// The model forms, in display order ("hydroshear", "fots", ...), and the effects that may follow one.
SHEARBENCH_API std::vector<std::string> model_names();
SHEARBENCH_API std::vector<std::string> effect_names();
// The shipped parameter sets (assets/params in shearbench's share folder).
SHEARBENCH_API std::vector<std::string> param_set_names();

// A residual loop's answer by the name of its run (docs/residuals/<name>, e.g. "twin_sphere35_hydroshear"): the
// model it selected and the report_params.json holding its fitted parameters, as a Config to complete with
// a sensor and an indenter.
SHEARBENCH_API Config loop_answer(const std::string& run_name);

// The benchmark workload's poses (BENCH_WORKLOAD.md, the peg grasp): [step][env * 2 + pad][7], X_EI of the
// peg in each pad's E, for steps 0..steps-1 (1..50) of `envs` environments.
SHEARBENCH_API std::vector<double> bench_poses(int envs, int steps);
// Its time between steps (s).
SHEARBENCH_API double bench_dt();

// "0.1.0".
SHEARBENCH_API std::string version();

}  // namespace shearbench
