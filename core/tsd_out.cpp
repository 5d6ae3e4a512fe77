#include "core/tsd_out.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/atomic_write.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace sb {


namespace {

void write_image_atomically(const std::string& path, const cv::Mat& image) {
  if (image.depth() != CV_8U) throw InputError(path, "frames must be 8-bit images");
  const cv::Mat packed = image.isContinuous() ? image : image.clone();
  write_png_atomic(path, packed.rows, packed.cols, packed.channels(), packed.data);
}

std::string poses_csv(const TsdSampleOut& s) {
  std::ostringstream o;
  o << "frame,t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  char line[256];
  for (std::size_t f = 0; f < s.X_EI.size(); ++f) {
    const Vec3 p = s.X_EI[f].translation();
    const auto q = quaternion_wxyz(s.X_EI[f]);
    std::snprintf(line, sizeof line, "%zu,%.4f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", f, double(f) * s.dt_s, p.x(),
                  p.y(), p.z(), q[0], q[1], q[2], q[3]);
    o << line;
  }
  return o.str();
}

std::string markers_csv(const TsdSampleOut& s) {
  std::ostringstream o;
  o << "frame,marker,du_px,dv_px\n";
  char line[128];
  for (std::size_t f = 0; f < s.disp_px.size(); ++f)
    for (std::size_t m = 0; m < s.disp_px[f].size(); ++m) {
      const Vec2& d = s.disp_px[f][m];
      if (std::isfinite(d.x()) && std::isfinite(d.y()))
        std::snprintf(line, sizeof line, "%zu,%zu,%.4f,%.4f\n", f, m, d.x(), d.y());
      else
        std::snprintf(line, sizeof line, "%zu,%zu,nan,nan\n", f, m);
      o << line;
    }
  return o.str();
}

}  // namespace

void write_tsd_dataset(const TsdDatasetOut& ds, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create output directory: " + ec.message());

  nlohmann::json j;
  j["format"] = "tsd/1";
  j["name"] = ds.name;
  j["kind"] = ds.kind;
  j["provenance"] = ds.provenance;
  j["license"] = ds.license;
  nlohmann::json rest = nlohmann::json::array();
  for (const auto& r : ds.markers_rest_px) rest.push_back({r.x(), r.y()});
  j["sensor"] = {
      {"model", ds.sensor_model},
      {"image_size_px", {ds.width_px, ds.height_px}},
      {"camera", {{"model", "orthographic"}, {"mm_per_px", ds.mm_per_px},
                  {"principal_px", {ds.principal_px.x(), ds.principal_px.y()}}}},
      {"gel", {{"size_m", {ds.gel_size_m.x(), ds.gel_size_m.y()}}, {"thickness_m", ds.gel_thickness_m},
               {"surface", "flat"}}},
      {"markers_rest_px", rest}};
  j["indenters"] = ds.indenters;
  for (const auto& [rel, text] : ds.mesh_files) {
    const fs::path path = fs::path(dir) / rel;
    fs::create_directories(path.parent_path(), ec);
    write_file_atomic(path.string(), text);
  }
  j["samples"] = nlohmann::json::array();

  for (const auto& s : ds.samples) {
    const fs::path sdir = fs::path(dir) / s.id;
    fs::create_directories(sdir, ec);
    if (ec) throw InputError(sdir.string(), "cannot create sample directory: " + ec.message());
    write_file_atomic((sdir / "poses.csv").string(), poses_csv(s));
    write_file_atomic((sdir / "markers.csv").string(), markers_csv(s));
    if (!s.frames.empty()) {
      fs::create_directories(sdir / "frames", ec);
      char name[32];
      for (std::size_t f = 0; f < s.frames.size(); ++f) {
        std::snprintf(name, sizeof name, "%06zu.png", f);
        write_image_atomically((sdir / "frames" / name).string(), s.frames[f]);
      }
    }
    nlohmann::json e = {{"id", s.id}, {"motion", s.motion}};
    if (!s.indenter.empty()) e["indenter"] = s.indenter;
    e["split"] = s.split;
    e["dt_s"] = s.dt_s;
    e["pose_known"] = s.pose_known;
    e["has_forces"] = false;
    e["has_frames"] = !s.frames.empty();
    for (const auto& [k, v] : s.extra.items()) e[k] = v;
    j["samples"].push_back(e);
  }
  write_file_atomic((fs::path(dir) / "dataset.json").string(), j.dump(1) + "\n");
}

}  // namespace sb
