#include "core/data/tsd_out.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/data/tsd.hpp"

namespace fs = std::filesystem;

namespace sb {
namespace {

void write_image_atomically(const std::string& path, const cv::Mat& image) {
  if (image.depth() != CV_8U) throw InputError(path, "frames must be 8-bit images");
  const cv::Mat packed = image.isContinuous() ? image : image.clone();
  write_png_atomic(path, packed.rows, packed.cols, packed.channels(), packed.data);
}

// The importers' description as the one in-memory dataset type; tsd.cpp writes every CSV and dataset.json.
Dataset as_dataset(const TsdDatasetOut& out) {
  Dataset ds;
  ds.name = out.name;
  ds.kind = out.kind;
  ds.provenance = out.provenance;
  ds.license = out.license;
  ds.sensor_model = out.sensor_model;
  ds.camera.width_px = out.width_px;
  ds.camera.height_px = out.height_px;
  ds.camera.mm_per_px = out.mm_per_px;
  ds.camera.principal_px = out.principal_px;
  ds.gel.size_m = out.gel_size_m;
  ds.gel.thickness_m = out.gel_thickness_m;
  if (out.camera) ds.camera = *out.camera;
  ds.gel.surface = out.gel_surface;
  ds.gel.radius_m = out.gel_radius_m;
  ds.gel.footprint_radius_m = out.gel_footprint_radius_m;
  ds.gel.markers_depth_m = out.markers_depth_m;
  ds.markers_rest_px = out.markers_rest_px;
  ds.sensor_extra = out.sensor_extra;
  for (const auto& [name, entry] : out.indenters.items()) {
    TsdIndenter ind;
    ind.mesh = entry.value("mesh", "");
    for (const auto& [k, v] : entry.items())
      if (k != "mesh") ind.extra[k] = v;
    ds.indenters[name] = ind;
  }
  for (const auto& s : out.samples) {
    TsdSampleInfo info;
    info.id = s.id;
    info.motion = s.motion;
    info.indenter = s.indenter;
    info.split = s.split;
    info.dt_s = s.dt_s;
    info.pose_known = s.pose_known;
    info.has_frames = std::any_of(s.frames.begin(), s.frames.end(), [](const cv::Mat& m) { return !m.empty(); });
    info.extra = s.extra;
    ds.samples.push_back(info);
  }
  return ds;
}

SampleData as_sample_data(const TsdSampleOut& s) {
  SampleData d;
  for (std::size_t f = 0; f < s.X_EI.size(); ++f) d.push_pose(double(f) * s.dt_s, s.X_EI[f]);
  d.markers_px = s.disp_px;
  return d;
}

}  // namespace

void write_tsd_dataset(const TsdDatasetOut& out, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create output directory: " + ec.message());
  for (const auto& [rel, text] : out.mesh_files) {
    const fs::path path = fs::path(dir) / rel;
    fs::create_directories(path.parent_path(), ec);
    write_file_atomic(path.string(), text);
  }
  const Dataset ds = as_dataset(out);
  std::vector<SampleData> data;
  for (const auto& s : out.samples) {
    const fs::path sdir = fs::path(dir) / s.id;
    const bool any_frame = std::any_of(s.frames.begin(), s.frames.end(), [](const cv::Mat& m) { return !m.empty(); });
    fs::create_directories(sdir / (any_frame ? "frames" : ""), ec);
    if (ec) throw InputError(sdir.string(), "cannot create sample directory: " + ec.message());
    for (std::size_t f = 0; f < s.frames.size(); ++f) {
      if (s.frames[f].empty()) {  // not imaged: then nothing may be tracked in it (read_sample's rule)
        if (f < s.disp_px.size() &&
            std::any_of(s.disp_px[f].begin(), s.disp_px[f].end(), [](const Vec2& d) { return d.allFinite(); }))
          throw std::invalid_argument("write_tsd_dataset: sample " + s.id + " frame " + std::to_string(f) +
                                      " has tracked markers but no image");
        continue;
      }
      write_image_atomically((sdir / "frames" / frame_file_name(f)).string(), s.frames[f]);
    }
    data.push_back(as_sample_data(s));
  }
  write_dataset(dir, ds, data);  // the samples' CSVs, then dataset.json last
}

}  // namespace sb
