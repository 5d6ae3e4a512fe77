// Reading tsd/1 datasets: dataset.json and, on demand, one sample's CSVs (tsd.hpp; writing: tsd_write.cpp).
#include "core/data/tsd.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "core/data/json_read.hpp"
#include "core/data/sensor_json.hpp"

namespace fs = std::filesystem;

namespace sb {

// ------------------------------------------------------------------------------------------ labels

const std::vector<std::string>& tsd_motions() {
  static const std::vector<std::string> m{"dilation", "shear", "twist", "roll", "slip", "free"};
  return m;
}
const std::vector<std::string>& tsd_splits() {
  static const std::vector<std::string> s{"calibration", "validation"};
  return s;
}
bool is_tsd_motion(const std::string& s) {
  return std::find(tsd_motions().begin(), tsd_motions().end(), s) != tsd_motions().end();
}
bool is_tsd_split(const std::string& s) {
  return std::find(tsd_splits().begin(), tsd_splits().end(), s) != tsd_splits().end();
}

std::string frame_file_name(std::size_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.png", frame);
  return name;
}

const TsdSampleInfo& Dataset::sample(const std::string& id) const {
  for (const auto& s : samples)
    if (s.id == id) return s;
  throw InputError(json_path(), "no sample '" + id + "' in dataset '" + name + "'");
}

std::string Dataset::json_path() const { return (fs::path(dir) / "dataset.json").string(); }

std::string Dataset::mesh_path(const std::string& indenter) const {
  const auto it = indenters.find(indenter);
  if (it == indenters.end()) throw InputError(json_path(), "unknown indenter '" + indenter + "'");
  return (fs::path(dir) / it->second.mesh).string();
}

std::vector<Pose> SampleData::poses() const {
  std::vector<Pose> out;
  out.reserve(frames());
  for (std::size_t k = 0; k < frames(); ++k) out.push_back(X_EI(k));
  return out;
}

void SampleData::push_pose(double t, const Pose& X) {
  const auto q = quaternion_wxyz(X);
  t_s.push_back(t);
  p_EI.push_back(X.translation());
  q_EI.push_back(Quat(q[0], q[1], q[2], q[3]));
}

// ------------------------------------------------------------------------------------------ CSV

namespace {

std::string read_whole_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file (missing or unreadable)");
  in.seekg(0, std::ios::end);
  std::string text(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  return text;
}

// A fast reader of simple numeric CSV (no quoting: tsd/1 files hold numbers only). It walks the file
// line by line, splits fields in place, and reports every problem as file:line:column. The current line and
// its fields are views into the reader's own copy of the text, so a reader is neither copied nor moved.
class CsvReader {
 public:
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;
  CsvReader(std::string path, const char* header, std::size_t columns)
      : path_(std::move(path)), text_(read_whole_file(path_)), columns_(columns) {
    if (!next_row()) fail(1, 1, "empty file (expected header '" + std::string(header) + "')");
    std::string_view h = line_;
    if (h.size() >= 3 && h.substr(0, 3) == "\xEF\xBB\xBF") h.remove_prefix(3);  // UTF-8 BOM
    if (h != header) fail(line_no_, 1, "wrong header '" + printable(h) + "' (expected '" + std::string(header) + "')");
  }

  // Advances to the next non-empty line and splits it; false at the end of the file.
  bool next_row() {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      line_ = std::string_view(text_).substr(pos_, end - pos_);
      if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
      pos_ = end + 1;
      ++line_no_;
      if (line_.empty()) {
        if (pos_ >= text_.size()) return false;  // the trailing newline
        fail(line_no_, 1, "empty line");
      }
      if (line_no_ > 1) split();
      return true;
    }
    return false;
  }

  int line() const { return line_no_; }
  int column(std::size_t i) const { return static_cast<int>(starts_[i]) + 1; }
  const std::string& path() const { return path_; }

  [[noreturn]] void fail(int line, int col, const std::string& what) const { throw InputError(path_, line, col, what); }
  [[noreturn]] void fail_at(std::size_t i, const std::string& what) const { fail(line_no_, column(i), what); }

  // A number, NaN/inf included (the caller decides what is allowed).
  double real(std::size_t i, const char* name) const {
    const std::string_view f = fields_[i];
    double v = 0;
    const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    if (ec != std::errc() || ptr != f.data() + f.size() || f.empty())
      fail_at(i, std::string(name) + ": expected a number, got '" + printable(f) + "'");
    return v;
  }
  double finite(std::size_t i, const char* name) const {
    const double v = real(i, name);
    if (!std::isfinite(v))
      fail_at(i, std::string(name) + ": value must be finite, got '" + printable(fields_[i]) + "'");
    return v;
  }
  long long index(std::size_t i, const char* name) const {
    const std::string_view f = fields_[i];
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    if (ec != std::errc() || ptr != f.data() + f.size() || f.empty() || v < 0)
      fail_at(i, std::string(name) + ": expected a non-negative integer, got '" + printable(f) + "'");
    return v;
  }

 private:
  void split() {
    fields_.clear();
    starts_.clear();
    std::size_t start = 0;
    for (;;) {
      const std::size_t comma = line_.find(',', start);
      const std::size_t end = comma == std::string_view::npos ? line_.size() : comma;
      std::string_view f = line_.substr(start, end - start);
      std::size_t lead = 0;
      while (lead < f.size() && (f[lead] == ' ' || f[lead] == '\t')) ++lead;
      f.remove_prefix(lead);
      while (!f.empty() && (f.back() == ' ' || f.back() == '\t')) f.remove_suffix(1);
      fields_.push_back(f);
      starts_.push_back(start + lead);
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (fields_.size() != columns_)
      fail(line_no_, 1, "expected " + std::to_string(columns_) + " columns, got " + std::to_string(fields_.size()));
  }

  std::string path_;
  std::string text_;
  std::size_t columns_;
  std::size_t pos_ = 0;
  int line_no_ = 0;
  std::string_view line_;
  std::vector<std::string_view> fields_;
  std::vector<std::size_t> starts_;
};

// The frame column must count 0, 1, 2, ... without gaps.
void expect_frame(const CsvReader& csv, long long frame, std::size_t expected) {
  if (frame == static_cast<long long>(expected)) return;
  if (frame < static_cast<long long>(expected))
    csv.fail_at(0, "frame " + std::to_string(frame) + " out of order (expected " + std::to_string(expected) + ")");
  csv.fail_at(0, "frame gap: frame " + std::to_string(frame) + " follows frame " +
                     std::to_string(static_cast<long long>(expected) - 1) + " (expected " + std::to_string(expected) +
                     ")");
}

}  // namespace

void read_poses_csv(const std::string& path, SampleData* out, Warnings* warnings) {
  CsvReader csv(path, kTsdPosesHeader, 9);
  static const char* names[] = {"frame", "t_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz"};
  out->t_s.clear();
  out->p_EI.clear();
  out->q_EI.clear();
  while (csv.next_row()) {
    expect_frame(csv, csv.index(0, "frame"), out->t_s.size());
    double v[9];
    for (std::size_t i = 1; i < 9; ++i) v[i] = csv.finite(i, names[i]);
    if (!out->t_s.empty() && !(v[1] > out->t_s.back()))
      csv.fail_at(1, "t_s must increase from frame to frame (" + std::to_string(v[1]) + " after " +
                         std::to_string(out->t_s.back()) + ")");
    const std::string where = path + ":" + std::to_string(csv.line()) + ":" + std::to_string(csv.column(5));
    Quat q;
    try {
      q = normalized_quaternion(v[5], v[6], v[7], v[8], where, warnings);
    } catch (const InputError& e) {
      csv.fail_at(5, e.detail());
    }
    // Keep a unit quaternion exactly as written so a rewrite reproduces the file; normalisation only
    // repairs the ones that normalized_quaternion warned about.
    const double n = std::sqrt(v[5] * v[5] + v[6] * v[6] + v[7] * v[7] + v[8] * v[8]);
    if (std::abs(n - 1.0) <= kQuatUnitTolerance) q = Quat(v[5], v[6], v[7], v[8]);
    out->t_s.push_back(v[1]);
    out->p_EI.emplace_back(v[2], v[3], v[4]);
    out->q_EI.push_back(q);
  }
  if (out->t_s.empty()) csv.fail(csv.line() + 1, 1, "no pose rows");
}

void read_markers_csv(const std::string& path, std::size_t n_frames, std::size_t n_markers, SampleData* out) {
  CsvReader csv(path, kTsdMarkersHeader, 4);
  const Vec2 lost(std::nan(""), std::nan(""));
  out->markers_px.assign(n_frames, std::vector<Vec2>(n_markers, lost));
  std::vector<char> seen(n_markers, 0);
  std::size_t seen_count = 0;
  long long current = -1;
  // A frame is complete when every marker has a row (lost ones as nan,nan).
  auto finish_frame = [&](int line, int col) {
    if (current < 0 || seen_count == n_markers) return;
    const auto missing = std::find(seen.begin(), seen.end(), 0) - seen.begin();
    csv.fail(line, col,
             "frame " + std::to_string(current) + " has " + std::to_string(seen_count) + " of " +
                 std::to_string(n_markers) + " marker rows (marker " + std::to_string(missing) +
                 " missing; write nan,nan for a lost marker)");
  };
  while (csv.next_row()) {
    const long long frame = csv.index(0, "frame");
    if (frame != current) {
      if (frame < current)
        csv.fail_at(0, "frame " + std::to_string(frame) + " out of order (after " + std::to_string(current) + ")");
      finish_frame(csv.line(), csv.column(0));
      if (frame != current + 1)
        csv.fail_at(0, "frame gap: frame " + std::to_string(frame) + " follows frame " + std::to_string(current));
      if (frame >= static_cast<long long>(n_frames))
        csv.fail_at(
            0, "frame " + std::to_string(frame) + " beyond the " + std::to_string(n_frames) + " frames of poses.csv");
      current = frame;
      std::fill(seen.begin(), seen.end(), 0);
      seen_count = 0;
    }
    const long long m = csv.index(1, "marker");
    if (m >= static_cast<long long>(n_markers))
      csv.fail_at(1, "marker index " + std::to_string(m) + " out of range (dataset has " + std::to_string(n_markers) +
                         " markers)");
    if (seen[m]) csv.fail_at(1, "duplicate row for marker " + std::to_string(m) + " in frame " + std::to_string(frame));
    const double du = csv.real(2, "du_px"), dv = csv.real(3, "dv_px");
    if (std::isinf(du)) csv.fail_at(2, "du_px: infinite value");
    if (std::isinf(dv)) csv.fail_at(3, "dv_px: infinite value");
    if (std::isnan(du) != std::isnan(dv)) csv.fail_at(2, "a lost marker must be nan in both du_px and dv_px");
    seen[m] = 1;
    ++seen_count;
    out->markers_px[frame][m] = Vec2(du, dv);
  }
  finish_frame(csv.line(), 1);
  if (current + 1 != static_cast<long long>(n_frames))
    csv.fail(csv.line(), 1,
             "markers end at frame " + std::to_string(current) + " but poses.csv has " + std::to_string(n_frames) +
                 " frames");
}

void read_forces_csv(const std::string& path, std::size_t n_frames, SampleData* out) {
  CsvReader csv(path, kTsdForcesHeader, 4);
  out->forces_n.clear();
  while (csv.next_row()) {
    expect_frame(csv, csv.index(0, "frame"), out->forces_n.size());
    if (out->forces_n.size() >= n_frames)
      csv.fail_at(0, "more force rows than the " + std::to_string(n_frames) + " frames of poses.csv");
    out->forces_n.emplace_back(csv.finite(1, "fx_n"), csv.finite(2, "fy_n"), csv.finite(3, "fz_n"));
  }
  if (out->forces_n.size() != n_frames)
    csv.fail(csv.line(), 1,
             "forces end after " + std::to_string(out->forces_n.size()) + " frames but poses.csv has " +
                 std::to_string(n_frames));
}

SampleData read_sample(const Dataset& ds, const std::string& sample_id, Warnings* warnings) {
  const TsdSampleInfo& info = ds.sample(sample_id);
  const fs::path dir = fs::path(ds.dir) / info.id;
  SampleData data;
  read_poses_csv((dir / "poses.csv").string(), &data, warnings);
  read_markers_csv((dir / "markers.csv").string(), data.frames(), ds.markers_rest_px.size(), &data);
  if (info.has_forces) read_forces_csv((dir / "forces.csv").string(), data.frames(), &data);
  if (info.has_frames) {
    for (std::size_t k = 0; k < data.frames(); ++k) {
      const std::string p = (dir / "frames" / frame_file_name(k)).string();
      // A frame that was not imaged (every marker lost, e.g. the TacTip set's pressed and sliding frames)
      // may lack its image: its path is empty. A frame with data must have one.
      const bool imaged = std::any_of(data.markers_px[k].begin(), data.markers_px[k].end(),
                                      [](const Vec2& d) { return d.allFinite(); });
      if (!fs::exists(p) && imaged) throw InputError(p, "frame image missing (sample has has_frames: true)");
      data.frame_paths.push_back(fs::exists(p) ? p : std::string());
    }
  }
  return data;
}

// ------------------------------------------------------------------------------------------ dataset.json

namespace {

using jsonin::child;

TsdSampleInfo parse_sample_info(const nlohmann::json& j, const std::string& file, const std::string& ptr) {
  jsonin::require_object(j, file, ptr);
  TsdSampleInfo s;
  s.id = jsonin::string(jsonin::member(j, "id", file, ptr), file, child(ptr, "id"));
  if (s.id.empty() || s.id.find_first_of("/\\") != std::string::npos || s.id == "." || s.id == "..")
    jsonin::fail(file, child(ptr, "id"), "sample id must be a plain folder name, got '" + s.id + "'");
  s.motion = jsonin::string(jsonin::member(j, "motion", file, ptr), file, child(ptr, "motion"));
  if (!is_tsd_motion(s.motion))
    jsonin::fail(file, child(ptr, "motion"),
                 "unknown motion '" + s.motion + "' (expected dilation, shear, twist, roll, slip or free)");
  s.indenter = jsonin::string(jsonin::member(j, "indenter", file, ptr), file, child(ptr, "indenter"));
  s.split = jsonin::string(jsonin::member(j, "split", file, ptr), file, child(ptr, "split"));
  if (!is_tsd_split(s.split))
    jsonin::fail(file, child(ptr, "split"), "unknown split '" + s.split + "' (expected calibration or validation)");
  s.dt_s = jsonin::positive_number(jsonin::member(j, "dt_s", file, ptr), file, child(ptr, "dt_s"));
  if (auto* v = jsonin::find(j, "pose_known")) s.pose_known = jsonin::boolean(*v, file, child(ptr, "pose_known"));
  if (auto* v = jsonin::find(j, "has_forces")) s.has_forces = jsonin::boolean(*v, file, child(ptr, "has_forces"));
  if (auto* v = jsonin::find(j, "has_frames")) s.has_frames = jsonin::boolean(*v, file, child(ptr, "has_frames"));
  for (const auto& [k, v] : j.items())
    if (k != "id" && k != "motion" && k != "indenter" && k != "split" && k != "dt_s" && k != "pose_known" &&
        k != "has_forces" && k != "has_frames")
      s.extra[k] = v;
  return s;
}

void parse_sensor(const nlohmann::json& j, const std::string& file, Dataset* ds) {
  const std::string ptr = "/sensor";
  jsonin::require_object(j, file, ptr);
  if (auto* v = jsonin::find(j, "model")) ds->sensor_model = jsonin::string(*v, file, child(ptr, "model"));
  const Vec2 size = jsonin::vec2(jsonin::member(j, "image_size_px", file, ptr), file, child(ptr, "image_size_px"));
  if (size.x() < 1 || size.y() < 1 || size != size.array().round().matrix())
    jsonin::fail(file, child(ptr, "image_size_px"), "expected two positive integers");
  ds->camera.width_px = static_cast<int>(size.x());
  ds->camera.height_px = static_cast<int>(size.y());

  const std::string cptr = child(ptr, "camera");
  const auto& cam = jsonin::member(j, "camera", file, ptr);
  parse_camera_model(cam, file, cptr, &ds->camera);
  if (!ds->camera.pinhole())
    ds->camera.mm_per_px =
        jsonin::positive_number(jsonin::member(cam, "mm_per_px", file, cptr), file, child(cptr, "mm_per_px"));
  ds->camera.principal_px =
      jsonin::vec2(jsonin::member(cam, "principal_px", file, cptr), file, child(cptr, "principal_px"));

  const std::string gptr = child(ptr, "gel");
  const auto& gel = jsonin::member(j, "gel", file, ptr);
  ds->gel.size_m = jsonin::vec2(jsonin::member(gel, "size_m", file, gptr), file, child(gptr, "size_m"));
  if (!(ds->gel.size_m.array() > 0).all()) jsonin::fail(file, child(gptr, "size_m"), "expected two positive numbers");
  ds->gel.thickness_m =
      jsonin::positive_number(jsonin::member(gel, "thickness_m", file, gptr), file, child(gptr, "thickness_m"));
  if (auto* v = jsonin::find(gel, "surface")) ds->gel.surface = jsonin::string(*v, file, child(gptr, "surface"));
  if (ds->gel.surface == "spherical_cap") {
    parse_spherical_cap(gel, file, gptr, &ds->gel);
  } else {
    for (const char* key : {"radius_m", "footprint_radius_m"})
      if (jsonin::find(gel, key)) jsonin::fail(file, child(gptr, key), "only a spherical_cap gel has this key");
  }
  if (auto* v = jsonin::find(j, "markers_depth_m"))
    ds->gel.markers_depth_m = parse_markers_depth(*v, ds->gel, file, child(ptr, "markers_depth_m"));
  if (gel_surface_is_mesh(ds->gel.surface) && !fs::exists(fs::path(ds->dir) / ds->gel.surface))
    jsonin::fail(file, child(gptr, "surface"), "gel mesh '" + ds->gel.surface + "' not found in " + ds->dir);

  const std::string mptr = child(ptr, "markers_rest_px");
  const auto& markers = jsonin::member(j, "markers_rest_px", file, ptr);
  if (!markers.is_array() || markers.empty()) jsonin::fail(file, mptr, "expected a non-empty array of [u, v]");
  ds->markers_rest_px.reserve(markers.size());
  for (std::size_t i = 0; i < markers.size(); ++i)
    ds->markers_rest_px.push_back(jsonin::vec2(markers[i], file, child(mptr, i)));

  for (const auto& [k, v] : j.items())
    if (k != "model" && k != "image_size_px" && k != "camera" && k != "gel" && k != "markers_rest_px" &&
        k != "markers_depth_m")
      ds->sensor_extra[k] = v;
}

}  // namespace

Dataset parse_dataset_json(const nlohmann::json& j, const std::string& file, const std::string& dir) {
  Dataset ds;
  ds.dir = dir;
  jsonin::require_object(j, file, "");
  const std::string format = jsonin::string(jsonin::member(j, "format", file, ""), file, "/format");
  if (format != "tsd/1") jsonin::fail(file, "/format", "unsupported format '" + format + "' (expected tsd/1)");
  ds.name = jsonin::string(jsonin::member(j, "name", file, ""), file, "/name");
  ds.kind = jsonin::string(jsonin::member(j, "kind", file, ""), file, "/kind");
  if (ds.kind != "real" && ds.kind != "synthetic")
    jsonin::fail(file, "/kind", "unknown kind '" + ds.kind + "' (expected real or synthetic)");
  if (auto* v = jsonin::find(j, "provenance")) ds.provenance = jsonin::string(*v, file, "/provenance");
  if (auto* v = jsonin::find(j, "license")) ds.license = jsonin::string(*v, file, "/license");
  parse_sensor(jsonin::member(j, "sensor", file, ""), file, &ds);

  const auto& indenters = jsonin::member(j, "indenters", file, "");
  jsonin::require_object(indenters, file, "/indenters");
  for (const auto& [name, entry] : indenters.items()) {
    const std::string ptr = child("/indenters", name);
    TsdIndenter ind;
    ind.mesh = jsonin::string(jsonin::member(entry, "mesh", file, ptr), file, child(ptr, "mesh"));
    // Meshes load lazily (build_indenter); the validator only checks that the file is there.
    if (!fs::exists(fs::path(dir) / ind.mesh))
      jsonin::fail(file, child(ptr, "mesh"), "mesh file '" + ind.mesh + "' not found in " + dir);
    for (const auto& [k, v] : entry.items())
      if (k != "mesh") ind.extra[k] = v;
    ds.indenters[name] = std::move(ind);
  }

  const auto& samples = jsonin::member(j, "samples", file, "");
  if (!samples.is_array()) jsonin::fail(file, "/samples", "expected an array");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string ptr = child("/samples", i);
    TsdSampleInfo s = parse_sample_info(samples[i], file, ptr);
    if (!ds.indenters.count(s.indenter))
      jsonin::fail(file, child(ptr, "indenter"), "indenter '" + s.indenter + "' is not listed under /indenters");
    for (const auto& other : ds.samples)
      if (other.id == s.id) jsonin::fail(file, child(ptr, "id"), "duplicate sample id '" + s.id + "'");
    ds.samples.push_back(std::move(s));
  }

  static const char* known[] = {"format", "name", "kind", "provenance", "license", "sensor", "indenters", "samples"};
  for (const auto& [k, v] : j.items())
    if (std::find(std::begin(known), std::end(known), k) == std::end(known)) ds.extra[k] = v;
  return ds;
}

void assign_calibration_split(Dataset& ds, const std::vector<std::string>& calibration_ids, const std::string& flag,
                              const std::vector<std::string>& validation_ids) {
  const auto listed = [](const std::vector<std::string>& ids, const std::string& id) {
    return std::find(ids.begin(), ids.end(), id) != ids.end();
  };
  for (const auto* ids : {&calibration_ids, &validation_ids})
    for (const auto& id : *ids)
      if (std::none_of(ds.samples.begin(), ds.samples.end(), [&](const auto& s) { return s.id == id; }))
        throw InputError(flag, "no sample '" + id + "' in " + ds.json_path());
  if (!validation_ids.empty())
    ds.samples.erase(
        std::remove_if(ds.samples.begin(), ds.samples.end(),
                       [&](const auto& s) { return !listed(calibration_ids, s.id) && !listed(validation_ids, s.id); }),
        ds.samples.end());
  for (auto& info : ds.samples) info.split = listed(calibration_ids, info.id) ? "calibration" : "validation";
}

Dataset read_dataset(const std::string& dir, Warnings* /*warnings*/) {
  if (!fs::is_directory(dir)) throw InputError(dir, "dataset folder not found");
  const std::string file = (fs::path(dir) / "dataset.json").string();
  return parse_dataset_json(jsonin::load_file(file), file, dir);
}

}  // namespace sb
