#include "core/workbench/session_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/base/strings.hpp"
#include "core/data/json_read.hpp"
#include "core/models/model_family.hpp"

namespace sb {
namespace {

using nlohmann::json;

// A pose as [x, y, z, qw, qx, qy, qz] (metres, w-first unit quaternion), as in tsd/1 poses.csv.
nlohmann::ordered_json pose_json(const Pose& X) {
  const Quat q(X.linear());
  const Vec3 p = X.translation();
  return nlohmann::ordered_json::array({p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()});
}

Pose pose_from_json(const json& j, const std::string& file, const std::string& ptr) {
  if (!j.is_array() || j.size() != 7) jsonin::fail(file, ptr, "expected [x, y, z, qw, qx, qy, qz]");
  double v[7];
  for (std::size_t i = 0; i < 7; ++i) v[i] = jsonin::finite_number(j[i], file, jsonin::child(ptr, i));
  const Quat q = normalized_quaternion(v[3], v[4], v[5], v[6], file + ": " + ptr, nullptr);
  return make_pose(Vec3(v[0], v[1], v[2]), q);
}

Vec3 vec3_from_json(const json& j, const std::string& file, const std::string& ptr) {
  if (!j.is_array() || j.size() != 3) jsonin::fail(file, ptr, "expected [x, y, z]");
  Vec3 v;
  for (std::size_t i = 0; i < 3; ++i) v[Eigen::Index(i)] = jsonin::finite_number(j[i], file, jsonin::child(ptr, i));
  return v;
}

CameraView camera_from_json(const json& j, const std::string& file, const std::string& ptr) {
  jsonin::reject_unknown_keys(j, {"position_mm", "focal_point_mm", "view_up"}, file, ptr);
  CameraView c;
  c.position = vec3_from_json(jsonin::member(j, "position_mm", file, ptr), file, jsonin::child(ptr, "position_mm"));
  c.focal_point =
      vec3_from_json(jsonin::member(j, "focal_point_mm", file, ptr), file, jsonin::child(ptr, "focal_point_mm"));
  c.view_up = vec3_from_json(jsonin::member(j, "view_up", file, ptr), file, jsonin::child(ptr, "view_up"));
  if ((c.position - c.focal_point).norm() <= 0 || c.view_up.norm() <= 0)
    jsonin::fail(file, ptr, "the camera must sit away from its focal point and have a view-up direction");
  return c;
}

// The one place a family's session key meets its field of SessionSource (const or not).
template <class Source>
auto& form_field(Source& source, const std::string& family_id) {
  for (auto [id, field] : {std::pair{"hydroshear", &SessionSource::hydroshear_id},
                           std::pair{"fots", &SessionSource::fots_id}, std::pair{"tacsl", &SessionSource::tacsl_id}})
    if (family_id == id) return source.*field;
  throw std::invalid_argument("the session keeps no form for model family '" + family_id + "'");
}

// /open's keys: a scene or dataset, the form shown per model family (keyed by the family's id), the rest.
void reject_unknown_open_keys(const json& open, const std::string& file) {
  std::vector<std::string> allowed = {"scene", "dataset", "sample"};
  for (const ModelFamily& f : model_families()) allowed.push_back(f.id);
  allowed.insert(allowed.end(), {"beside_hydroshear", "indenter_mesh", "indenter_scale", "param_set"});
  jsonin::require_object(open, file, "/open");
  for (const auto& item : open.items())
    if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
      jsonin::fail(file, jsonin::child("/open", item.key()),
                   "unknown key (expected one of: " + join(allowed, ", ") + ")");
}

std::string optional_string(const json& j, const char* key, const std::string& file, const std::string& ptr,
                            const std::string& fallback) {
  const json* v = jsonin::find(j, key);
  return v ? jsonin::string(*v, file, jsonin::child(ptr, key)) : fallback;
}

}  // namespace

std::string& SessionSource::form_shown(const std::string& family_id) { return form_field(*this, family_id); }

const std::string& SessionSource::form_shown(const std::string& family_id) const {
  return form_field(*this, family_id);
}

nlohmann::ordered_json session_to_json(const SessionFile& s) {
  nlohmann::ordered_json j;
  j["format"] = "shearbench-session";
  j["version"] = SessionFile::kFormatVersion;
  j["open"] = {{"scene", s.open.scene_path}, {"dataset", s.open.dataset_dir}, {"sample", s.open.sample_id}};
  for (const ModelFamily& f : model_families()) j["open"][f.id] = s.open.form_shown(f.id);
  j["open"]["indenter_mesh"] = s.open.indenter_mesh;
  j["open"]["indenter_scale"] = s.open.indenter_scale;
  j["open"]["param_set"] = s.open.param_set;
  // Written only when used, so sessions without it stay readable by builds from before it.
  if (!s.open.beside_hydroshear.empty()) j["open"]["beside_hydroshear"] = s.open.beside_hydroshear;
  j["params"] = s.params;
  nlohmann::ordered_json path = nlohmann::ordered_json::array();
  for (const auto& X : s.path) path.push_back(pose_json(X));
  j["path_X_EI"] = path;
  j["step"] = s.step;
  j["display"] = {{"auto_scale", s.auto_scale}, {"arrow_gain", s.arrow_gain}, {"colour_max_px", s.colour_max_px}};
  if (s.camera) {
    const auto vec = [](const Vec3& v) { return nlohmann::ordered_json::array({v.x(), v.y(), v.z()}); };
    j["display"]["camera"] = {{"position_mm", vec(s.camera->position)},
                              {"focal_point_mm", vec(s.camera->focal_point)},
                              {"view_up", vec(s.camera->view_up)}};
  }
  if (!s.marker_model.empty()) j["display"]["marker_model"] = s.marker_model;
  if (s.colour_map != ColourMap::kViridis) j["display"]["colour_map"] = colour_map_name(s.colour_map);
  if (!s.frame_backdrops.empty()) {
    j["display"]["frame_backdrops"] = nlohmann::ordered_json::object();
    for (const auto& [panel, b] : s.frame_backdrops) j["display"]["frame_backdrops"][panel] = backdrop_name(b);
  }
  if (!s.residual_file.empty())
    j["residual"] = {
        {"file", s.residual_file}, {"residual_fields", s.residual_fields}, {"corrected", s.residual_corrected}};
  return j;
}

namespace {

// One of `names`' values by its name; fails naming the pointer and the choices.
template <class T, std::size_t N>
T choice_by_name(const json& v, const std::array<T, N>& choices, std::string (*name)(T), const std::string& file,
                 const std::string& pointer) {
  const std::string given = jsonin::string(v, file, pointer);
  std::string all;
  for (T c : choices) {
    if (name(c) == given) return c;
    all += (all.empty() ? "" : ", ") + ("'" + name(c) + "'");
  }
  jsonin::fail(file, pointer, "expected one of " + all + ", got '" + given + "'");
}

void read_display_choices(const json& d, const std::string& file, SessionFile& s) {
  if (const json* v = jsonin::find(d, "marker_model"))
    s.marker_model = jsonin::string(*v, file, "/display/marker_model");
  if (const json* v = jsonin::find(d, "colour_map"))
    s.colour_map = choice_by_name(*v, kColourMaps, colour_map_name, file, "/display/colour_map");
  if (const json* b = jsonin::find(d, "frame_backdrops")) {
    jsonin::require_object(*b, file, "/display/frame_backdrops");
    for (const auto& [panel, v] : b->items())
      s.frame_backdrops.emplace_back(
          panel, choice_by_name(v, kFrameBackdrops, backdrop_name, file, "/display/frame_backdrops/" + panel));
  }
}

}  // namespace

SessionFile session_from_json(const json& j, const std::string& file) {
  jsonin::reject_unknown_keys(j, {"format", "version", "open", "params", "path_X_EI", "step", "display", "residual"},
                              file, "");
  if (jsonin::string(jsonin::member(j, "format", file, ""), file, "/format") != "shearbench-session")
    jsonin::fail(file, "/format", "not a shearbench session file");
  const int version = jsonin::integer(jsonin::member(j, "version", file, ""), file, "/version");
  if (version < SessionFile::kOldestReadableVersion || version > SessionFile::kFormatVersion)
    jsonin::fail(file, "/version",
                 "unsupported session version " + std::to_string(version) + " (this build reads " +
                     std::to_string(SessionFile::kOldestReadableVersion) + " to " +
                     std::to_string(SessionFile::kFormatVersion) + ")");
  if (version < 2 && jsonin::find(j, "residual"))
    jsonin::fail(file, "/residual", "a version 1 session has no residual section");
  SessionFile s;
  const json& open = jsonin::member(j, "open", file, "");
  reject_unknown_open_keys(open, file);
  s.open.scene_path = optional_string(open, "scene", file, "/open", "");
  s.open.dataset_dir = optional_string(open, "dataset", file, "/open", "");
  s.open.sample_id = optional_string(open, "sample", file, "/open", "");
  for (const ModelFamily& f : model_families()) {
    std::string& form = s.open.form_shown(f.id);
    form = optional_string(open, f.id.c_str(), file, "/open", form);
  }
  s.open.beside_hydroshear = optional_string(open, "beside_hydroshear", file, "/open", "");
  s.open.indenter_mesh = optional_string(open, "indenter_mesh", file, "/open", "");
  // Version 1 files predate parameter sets: their models started from the published values.
  s.open.param_set = optional_string(open, "param_set", file, "/open", version < 2 ? "published" : s.open.param_set);
  if (const json* v = jsonin::find(open, "indenter_scale"))
    s.open.indenter_scale = jsonin::positive_number(*v, file, "/open/indenter_scale");

  if (const json* p = jsonin::find(j, "params")) {
    jsonin::require_object(*p, file, "/params");
    for (const auto& [id, table] : p->items()) jsonin::require_object(table, file, jsonin::child("/params", id));
    s.params = *p;
  }
  if (const json* path = jsonin::find(j, "path_X_EI")) {
    if (!path->is_array()) jsonin::fail(file, "/path_X_EI", "expected an array of poses");
    s.path.reserve(path->size());
    for (std::size_t k = 0; k < path->size(); ++k)
      s.path.push_back(pose_from_json((*path)[k], file, jsonin::child("/path_X_EI", k)));
  }
  if (const json* step = jsonin::find(j, "step")) {
    s.step = jsonin::integer(*step, file, "/step");
    if (s.step < -1 || s.step >= static_cast<int>(std::max<std::size_t>(s.path.size(), 1)))
      jsonin::fail(
          file, "/step",
          "step " + std::to_string(s.step) + " is outside the path (" + std::to_string(s.path.size()) + " poses)");
  }
  if (const json* d = jsonin::find(j, "display")) {
    jsonin::reject_unknown_keys(
        *d, {"auto_scale", "arrow_gain", "colour_max_px", "camera", "marker_model", "colour_map", "frame_backdrops"},
        file, "/display");
    read_display_choices(*d, file, s);
    if (const json* c = jsonin::find(*d, "camera")) s.camera = camera_from_json(*c, file, "/display/camera");
    if (const json* v = jsonin::find(*d, "auto_scale")) s.auto_scale = jsonin::boolean(*v, file, "/display/auto_scale");
    if (const json* v = jsonin::find(*d, "arrow_gain")) {
      s.arrow_gain = jsonin::finite_number(*v, file, "/display/arrow_gain");
      if (s.arrow_gain < 0) jsonin::fail(file, "/display/arrow_gain", "must be >= 0");
    }
    if (const json* v = jsonin::find(*d, "colour_max_px")) {
      s.colour_max_px = jsonin::finite_number(*v, file, "/display/colour_max_px");
      if (s.colour_max_px < 0) jsonin::fail(file, "/display/colour_max_px", "must be >= 0");
    }
  }
  if (const json* r = jsonin::find(j, "residual")) {
    jsonin::reject_unknown_keys(*r, {"file", "residual_fields", "corrected"}, file, "/residual");
    s.residual_file = jsonin::string(jsonin::member(*r, "file", file, "/residual"), file, "/residual/file");
    if (const json* v = jsonin::find(*r, "residual_fields"))
      s.residual_fields = jsonin::boolean(*v, file, "/residual/residual_fields");
    if (const json* v = jsonin::find(*r, "corrected"))
      s.residual_corrected = jsonin::boolean(*v, file, "/residual/corrected");
  }
  return s;
}

SessionFile load_session_file(const std::string& path) { return session_from_json(jsonin::load_file(path), path); }

bool is_session_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return false;
  const json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) return false;
  const auto it = j.find("format");
  return it != j.end() && it->is_string() && it->get<std::string>() == "shearbench-session";
}

void require_overwritable_session(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path, "is a folder, not a session file: choose a file name such as session.json");
  if (std::filesystem::file_size(path, ec) == 0 && !ec) return;  // an empty file holds nothing to lose
  if (!is_session_file(path))
    throw InputError(path,
                     "exists and is not a shearbench session file (no \"format\": \"shearbench-session\"); "
                     "not overwritten: choose another session path");
}

void save_session_file(const std::string& path, const SessionFile& s) {
  require_overwritable_session(path);
  write_file_atomic(path, session_to_json(s).dump(1) + "\n");
}

}  // namespace sb
