#pragma once
// tsd/1 tactile shear datasets (/work/shared/data/FORMAT.md): one folder with dataset.json, indenter
// meshes and per-sample CSVs. Reading is lazy: read_dataset parses dataset.json only (the sample list);
// read_sample loads one sample's CSVs on demand. Every malformed thing throws InputError naming the file,
// line and column. Writing is atomic per file (temporary file + rename), dataset.json last, and exact:
// doubles are written in their shortest round-trip form.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/geometry/pose.hpp"
#include "core/sensor/camera.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

// The motion labels and splits tsd/1 allows, in display order.
const std::vector<std::string>& tsd_motions();  // dilation shear twist roll slip free
const std::vector<std::string>& tsd_splits();   // calibration validation
bool is_tsd_motion(const std::string& s);
bool is_tsd_split(const std::string& s);
// A frame image's file name in a sample's frames/ folder: 000042.png for frame 42.
std::string frame_file_name(std::size_t frame);

struct TsdSampleInfo {
  std::string id;
  std::string motion = "free";
  std::string indenter;  // key into Dataset::indenters
  std::string split = "calibration";
  double dt_s = 0.02;
  bool pose_known = true;
  bool has_forces = false;
  bool has_frames = false;
  nlohmann::json extra = nlohmann::json::object();  // unknown fields, preserved on write
};

struct TsdIndenter {
  std::string mesh;  // path relative to the dataset folder, e.g. meshes/sphere_r4.obj
  nlohmann::json extra = nlohmann::json::object();
};

struct Dataset {
  std::string dir;  // folder it was read from (empty when built in memory)
  std::string name;
  std::string kind = "synthetic";  // real | synthetic
  std::string provenance;
  std::string license;
  std::string sensor_model = kDefaultSensorModel;
  Camera camera;  // includes image_size_px (width_px, height_px)
  GelSpec gel;
  std::vector<Vec2> markers_rest_px;
  std::map<std::string, TsdIndenter> indenters;
  std::vector<TsdSampleInfo> samples;
  nlohmann::json extra = nlohmann::json::object();         // unknown top-level fields
  nlohmann::json sensor_extra = nlohmann::json::object();  // unknown fields of "sensor"

  // Throws InputError(dataset.json) for an unknown id.
  const TsdSampleInfo& sample(const std::string& id) const;
  std::string json_path() const;
  // Absolute or dir-relative path of an indenter's mesh.
  std::string mesh_path(const std::string& indenter) const;
};

// One sample's data. Poses are kept as read (translation + unit quaternion, w-first) so a write
// reproduces the file exactly; X_EI(k) builds the pose.
struct SampleData {
  std::vector<double> t_s;
  std::vector<Vec3> p_EI;
  std::vector<Quat> q_EI;
  std::vector<std::vector<Vec2>> markers_px;  // [frame][marker] displacement; NaN where lost
  std::vector<Vec3> forces_n;                 // [frame]; empty when the sample has none
  std::vector<std::string> frame_paths;       // [frame]; empty when the sample has none

  std::size_t frames() const { return t_s.size(); }
  Pose X_EI(std::size_t k) const { return make_pose(p_EI[k], q_EI[k]); }
  std::vector<Pose> poses() const;
  void push_pose(double t, const Pose& X);  // appends a frame's time and pose (markers separately)
};

// Reassigns the splits of a dataset published without them (e.g. the FOTS press/shear pair): the listed
// samples become the calibration split, every other sample the validation split. An id the dataset does
// not have is an InputError naming `flag` (the option that gave it) and the dataset file. With
// `validation_ids` the listed samples validate and every sample in neither list is dropped (a fixed subset
// of a large set, e.g. the TacTip set's parameter set).
void assign_calibration_split(Dataset& ds, const std::vector<std::string>& calibration_ids, const std::string& flag,
                              const std::vector<std::string>& validation_ids = {});

// Parses and validates dataset.json in `dir` (format, fields, motions, splits, indenter references and
// that each referenced mesh file exists). Samples are not loaded.
Dataset read_dataset(const std::string& dir, Warnings* warnings = nullptr);
Dataset parse_dataset_json(const nlohmann::json& j, const std::string& file, const std::string& dir);

// Loads and validates one sample's CSVs (and that its frame images exist when has_frames).
SampleData read_sample(const Dataset& ds, const std::string& sample_id, Warnings* warnings = nullptr);

// The individual CSV readers, for tools that hold a single file. `n_markers` bounds marker indices.
void read_poses_csv(const std::string& path, SampleData* out, Warnings* warnings);
void read_markers_csv(const std::string& path, std::size_t n_frames, std::size_t n_markers, SampleData* out);
void read_forces_csv(const std::string& path, std::size_t n_frames, SampleData* out);

// The CSV headers of tsd/1 (FORMAT.md), as the reader expects and the writer writes them.
inline constexpr const char* kTsdPosesHeader = "frame,t_s,x_m,y_m,z_m,qw,qx,qy,qz";
inline constexpr const char* kTsdMarkersHeader = "frame,marker,du_px,dv_px";
inline constexpr const char* kTsdForcesHeader = "frame,fx_n,fy_n,fz_n";

// Writing (tsd_write.cpp). write_sample writes <dir>/<id>/poses.csv, markers.csv and (when has_forces) forces.csv, each
// atomically; it does not copy frame images or meshes. write_dataset_json writes dataset.json
// atomically. write_dataset writes every sample, then dataset.json, so a reader never sees a
// dataset.json that lists samples not yet written. `samples[i]` belongs to `ds.samples[i]`.
void write_sample(const std::string& dir, const TsdSampleInfo& info, const SampleData& data, std::size_t n_markers);
nlohmann::ordered_json dataset_to_json(const Dataset& ds);  // FORMAT.md field order
void write_dataset_json(const std::string& dir, const Dataset& ds);
void write_dataset(const std::string& dir, const Dataset& ds, const std::vector<SampleData>& samples);

// write_file_atomic (core/base/atomic_write.hpp) writes every file of a dataset.

}  // namespace sb
