// Writing tsd/1 datasets: the sample CSVs and dataset.json, each file atomically (tsd.hpp).
#include <charconv>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "core/data/sensor_json.hpp"
#include "core/data/tsd.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

// Shortest text that reads back to the same double; NaN as "nan".
void append_number(std::string& s, double v) {
  if (std::isnan(v)) {
    s += "nan";
    return;
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}
void append_index(std::string& s, std::size_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

}  // namespace

void write_sample(const std::string& dir, const TsdSampleInfo& info, const SampleData& data, std::size_t n_markers) {
  const fs::path sdir = fs::path(dir) / info.id;
  const std::size_t n = data.frames();
  if (data.p_EI.size() != n || data.q_EI.size() != n || data.markers_px.size() != n)
    throw std::invalid_argument("write_sample: sample '" + info.id + "' has inconsistent frame counts");
  std::string poses = std::string(kTsdPosesHeader) + "\n";
  poses.reserve(n * 160);
  for (std::size_t k = 0; k < n; ++k) {
    append_index(poses, k);
    const double v[8] = {data.t_s[k],      data.p_EI[k].x(), data.p_EI[k].y(), data.p_EI[k].z(),
                         data.q_EI[k].w(), data.q_EI[k].x(), data.q_EI[k].y(), data.q_EI[k].z()};
    for (double x : v) {
      poses += ',';
      append_number(poses, x);
    }
    poses += '\n';
  }
  std::string markers = std::string(kTsdMarkersHeader) + "\n";
  markers.reserve(n * n_markers * 32);
  for (std::size_t k = 0; k < n; ++k) {
    if (data.markers_px[k].size() != n_markers)
      throw std::invalid_argument("write_sample: frame " + std::to_string(k) + " of '" + info.id + "' has " +
                                  std::to_string(data.markers_px[k].size()) + " markers, expected " +
                                  std::to_string(n_markers));
    for (std::size_t m = 0; m < n_markers; ++m) {
      append_index(markers, k);
      markers += ',';
      append_index(markers, m);
      markers += ',';
      append_number(markers, data.markers_px[k][m].x());
      markers += ',';
      append_number(markers, data.markers_px[k][m].y());
      markers += '\n';
    }
  }
  write_file_atomic((sdir / "poses.csv").string(), poses);
  write_file_atomic((sdir / "markers.csv").string(), markers);
  if (info.has_forces) {
    if (data.forces_n.size() != n)
      throw std::invalid_argument("write_sample: '" + info.id + "' has_forces but forces_n has the wrong size");
    std::string forces = std::string(kTsdForcesHeader) + "\n";
    for (std::size_t k = 0; k < n; ++k) {
      append_index(forces, k);
      for (int i = 0; i < 3; ++i) {
        forces += ',';
        append_number(forces, data.forces_n[k][i]);
      }
      forces += '\n';
    }
    write_file_atomic((sdir / "forces.csv").string(), forces);
  }
}

nlohmann::ordered_json dataset_to_json(const Dataset& ds) {
  // ordered_json keeps the FORMAT.md field order, which makes the files easy to read and diff.
  nlohmann::ordered_json j;
  j["format"] = "tsd/1";
  j["name"] = ds.name;
  j["kind"] = ds.kind;
  j["provenance"] = ds.provenance;
  j["license"] = ds.license;
  nlohmann::ordered_json sensor;
  sensor["model"] = ds.sensor_model;
  sensor["image_size_px"] = {ds.camera.width_px, ds.camera.height_px};
  sensor["camera"] = camera_to_json(ds.camera);
  sensor["gel"] = {{"size_m", {ds.gel.size_m.x(), ds.gel.size_m.y()}},
                   {"thickness_m", ds.gel.thickness_m},
                   {"surface", ds.gel.surface}};
  if (ds.gel.surface == "spherical_cap") {
    sensor["gel"]["radius_m"] = ds.gel.radius_m;
    sensor["gel"]["footprint_radius_m"] = ds.gel.footprint_radius_m;
  }
  // A GelSight-Mini-like sensor (orthographic, markers on the surface) keeps the block it always had.
  if (!is_classic_sensor(ds.camera, ds.gel)) sensor["markers_depth_m"] = ds.gel.markers_depth_m;
  nlohmann::ordered_json markers = nlohmann::ordered_json::array();
  for (const Vec2& m : ds.markers_rest_px) markers.push_back({m.x(), m.y()});
  sensor["markers_rest_px"] = markers;
  for (const auto& [k, v] : ds.sensor_extra.items()) sensor[k] = v;
  j["sensor"] = sensor;
  nlohmann::ordered_json indenters = nlohmann::ordered_json::object();
  for (const auto& [name, ind] : ds.indenters) {
    nlohmann::ordered_json e{{"mesh", ind.mesh}};
    for (const auto& [k, v] : ind.extra.items()) e[k] = v;
    indenters[name] = e;
  }
  j["indenters"] = indenters;
  nlohmann::ordered_json samples = nlohmann::ordered_json::array();
  for (const auto& s : ds.samples) {
    nlohmann::ordered_json e{
        {"id", s.id},     {"motion", s.motion},         {"indenter", s.indenter},     {"split", s.split},
        {"dt_s", s.dt_s}, {"pose_known", s.pose_known}, {"has_forces", s.has_forces}, {"has_frames", s.has_frames}};
    for (const auto& [k, v] : s.extra.items()) e[k] = v;
    samples.push_back(e);
  }
  j["samples"] = samples;
  for (const auto& [k, v] : ds.extra.items()) j[k] = v;
  return j;
}

void write_dataset_json(const std::string& dir, const Dataset& ds) {
  // nlohmann prints doubles in their shortest round-trip form, so the metadata round-trips exactly too.
  write_file_atomic((fs::path(dir) / "dataset.json").string(), dataset_to_json(ds).dump(2) + "\n");
}

void write_dataset(const std::string& dir, const Dataset& ds, const std::vector<SampleData>& samples) {
  if (samples.size() != ds.samples.size())
    throw std::invalid_argument("write_dataset: " + std::to_string(samples.size()) + " sample data for " +
                                std::to_string(ds.samples.size()) + " samples");
  for (std::size_t i = 0; i < samples.size(); ++i)
    write_sample(dir, ds.samples[i], samples[i], ds.markers_rest_px.size());
  write_dataset_json(dir, ds);
}

}  // namespace sb
