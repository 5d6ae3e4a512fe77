#pragma once
// A scene: the sensor, the indenter, per-model parameters, and either a trajectory of the indenter in
// the elastomer frame or a tsd/1 dataset sample to replay. JSON schema (scenes/*.json):
//
// {
//   "name": "press_sphere",
//   "motion": "dilation",                                          (optional tsd/1 label, default free)
//   "sensor": {"gel": "flat" | "data:meshes/gel_gelsight_mini.obj", "markers": "7x9" | "11x9",
//              "camera": {"mm_per_px": 0.0634, "principal_px": [159.5, 119.5], "image_size_px": [320, 240]}},
//   "indenter": {"shape": "sphere", "radius_m": 0.004}            (see IndenterSpec)
//             | {"shape": "mesh", "mesh": "data:meshes/cow.obj", "scale": 0.002},
//   "params": {"hydroshear": {"mu": 0.5}, "fots": {...}},          (optional, per model id)
//   "trajectory": {"dt_s": 0.02, "substeps": 1,
//                  "keyframes": [{"t_s": 0, "xyz_m": [0, 0, 0.0045], "rpy_deg": [0, 0, 0]}, ...]},
//   "dataset": {"path": "data:twin/twin_sphere35", "sample": "dil_00"}   (instead of "trajectory")
// }
// Keyframes are X_EI (indenter origin and roll-pitch-yaw, extrinsic xyz, in E); poses between them
// are interpolated linearly in position and by slerp in rotation, sampled every dt_s from the first
// keyframe's time; the last keyframe is always included (as a shorter final step when the span is not
// a multiple of dt_s). "rpy_deg" is optional (default 0). "substeps" (default 1) asks the model for
// that many sub-steps per sample.
// "sensor" is optional (default: make_default_sensor()); a mesh gel is placed with
// gelsight_mini_gel_in_E. A "dataset" scene takes its sensor, indenter, poses, dt and motion from the
// tsd/1 sample; an "indenter" entry in the scene replaces the dataset's mesh (e.g. an exact sphere).
// "data:" paths resolve through the data root, other relative paths against the scene's folder.
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/geometry/indenter.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

struct Keyframe {
  double t_s = 0;
  Vec3 p_EI = Vec3::Zero();
  Quat q_EI = Quat::Identity();
};

struct Scene {
  std::string name;
  std::string path;             // the file it was read from
  std::string motion = "free";  // tsd/1 motion label (simulate writes it into the dataset)
  int substeps = 1;
  std::shared_ptr<const Sensor> sensor;
  std::string sensor_model = kDefaultSensorModel;  // a dataset replay's sensor (picks the default parameter set)
  IndenterSpec indenter_spec;
  std::map<std::string, nlohmann::json> params;  // model id -> {name: value}
  double dt_s = 0.02;
  std::vector<Keyframe> keyframes;
  std::vector<Pose> X_EI;   // sampled trajectory, one pose per step
  std::vector<double> t_s;  // the time of each pose
  std::string dataset_dir;  // when replaying a dataset
  std::string sample_id;
};

// Throws InputError naming the file and the JSON pointer of the bad entry.
Scene load_scene(const std::string& path, const std::string& data_root);
Scene parse_scene(const nlohmann::json& j, const std::string& where, const std::string& data_root,
                  const std::string& base_dir);
std::vector<Pose> sample_trajectory(const std::vector<Keyframe>& keyframes, double dt_s);
// The times sample_trajectory samples at.
std::vector<double> trajectory_times(const std::vector<Keyframe>& keyframes, double dt_s);
// Parses an indenter description (see IndenterSpec); `pointer` locates it in `where` for errors.
IndenterSpec parse_indenter_spec(const nlohmann::json& j, const std::string& where, const std::string& pointer,
                                 const std::string& data_root, const std::string& base_dir);
// Parses a scene's "sensor" block (the schema above); errors name `where` and the pointer /sensor/...
std::shared_ptr<const Sensor> parse_scene_sensor(const nlohmann::json& j, const std::string& where,
                                                 const std::string& data_root, const std::string& base_dir);
Pose rpy_pose(const Vec3& xyz_m, const Vec3& rpy_deg);

}  // namespace sb
