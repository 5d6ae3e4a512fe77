#pragma once
// The workbench session file: what the user made, so it can be saved, reopened, autosaved and offered
// back after a crash. JSON with a format version; written atomically; every bad value is reported as
// "file: /json/pointer: what". Parameter tables are kept as JSON here and validated by the models'
// ParamSet when applied; the form shown per model family is keyed by the family's id (core/models/model_family.hpp).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration/param_sets.hpp"
#include "core/geometry/pose.hpp"
#include "core/workbench/frame_backdrop.hpp"

namespace sb {

// What is open (as for `shearbench gui`): a scene, or a dataset sample, and the model variants shown.
// The session file keeps it, and the CLI's gui and render fill it from their flags.
// "auto": the HydroShear variant the residual loop selects on the data the parameter set was fitted on
// (hydroshear-contact on the twin sets) when the set holds fitted values for it, else none.
inline constexpr const char* kBesideHydroshearAuto = "auto";
inline constexpr const char* kBesideHydroshearAutoModel = "hydroshear-contact";

struct SessionSource {
  std::string scene_path;   // empty: scenes/default.json
  std::string dataset_dir;  // replay a tsd/1 dataset instead of a scene
  std::string sample_id;    // empty: the dataset's first sample
  std::string hydroshear_id =
      "hydroshear";                // or hydroshear-layer, hydroshear-stick, hydroshear-layer-stick, hydroshear-contact
  std::string fots_id = "fots";    // or fots-reimpl
  std::string tacsl_id = "tacsl";  // or tacsl-normalized
  // The form shown in the panel of the model family `family_id` (core/models/model_family.hpp): one of the three
  // above, whose session-file key and gui flag are the family's id. Throws std::invalid_argument for a family
  // without a field here.
  std::string& form_shown(const std::string& family_id);
  const std::string& form_shown(const std::string& family_id) const;
  // A HydroShear variant in a panel of its own beside HydroShear's (empty: none), to compare a model-form
  // correction with the model it corrects. The first view shows "auto" (above); a session file
  // without the key shows none, as before.
  std::string beside_hydroshear = kBesideHydroshearAuto;
  std::string indenter_mesh;      // replaces the scene's indenter by this mesh ("data:meshes/cow.obj")
  double indenter_scale = 0.002;  // file units to metres for indenter_mesh
  std::string param_set;          // the parameter set the models start from (empty: the default for the sensor)
};

// The 3D view's camera (millimetres in E, as the view draws): where it is, what it looks at, which way is up.
struct CameraView {
  Vec3 position = Vec3::Zero();
  Vec3 focal_point = Vec3::Zero();
  Vec3 view_up = Vec3::UnitZ();
};

struct SessionFile {
  // Version 2 added the optional "residual" section, version 3 the optional camera under "display", version 4
  // the marker model, colour map and frame backdrops under "display"; older files are still read.
  static constexpr int kFormatVersion = 4;
  static constexpr int kOldestReadableVersion = 1;
  SessionSource open;
  // What the user did: every model's parameters (model id -> table), the pose path X_EI(0..n-1)
  // including drags, and the step shown.
  nlohmann::json params = nlohmann::json::object();
  std::vector<Pose> path;
  int step = -1;
  // How it is shown.
  bool auto_scale = true;
  double arrow_gain = 0.0;  // 0: the workbench's default
  double colour_max_px = 0.0;
  std::optional<CameraView> camera;  // none: the default (iso) view
  // Written only when chosen, so files without them stay readable by older builds: the model whose field the 3D
  // view's markers show (its id; empty: the first panel's), the colour map, and each field panel's frame
  // backdrop by panel title (a panel not listed: dimmed).
  std::string marker_model;
  ColourMap colour_map = ColourMap::kViridis;
  std::vector<std::pair<std::string, FrameBackdrop>> frame_backdrops;
  // A residual analysis shown in the Residual section (empty: none) and its two switches.
  std::string residual_file;
  bool residual_fields = false;
  bool residual_corrected = true;
};

nlohmann::ordered_json session_to_json(const SessionFile& s);
// `file` names the source in errors.
SessionFile session_from_json(const nlohmann::json& j, const std::string& file);
SessionFile load_session_file(const std::string& path);
// Writes `s` atomically. Never overwrites a file that is not a shearbench session file (a scene, a
// dataset.json, anything else the user pointed the Session field at): throws InputError naming it.
void save_session_file(const std::string& path, const SessionFile& s);
// True when `path` holds a JSON object whose "format" is "shearbench-session" (readable or not by this build).
bool is_session_file(const std::string& path);
// Throws InputError when `path` exists and is not a session file (what save_session_file checks first).
void require_overwritable_session(const std::string& path);

}  // namespace sb
