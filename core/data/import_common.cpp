// What the importers share (import_common.hpp).
#include "core/data/import_common.hpp"

#include <filesystem>
#include <sstream>

#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/data/obj_writers.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

constexpr const char* kUnknownContact =
    "unknown_contact";  // GelSight Mini recordings (SOURCE.md), used when the file has none

}  // namespace

const char* const kImportAxisNote =
    "Axes: the camera looks along +z_E from inside the gel, so image u (right), v (down) are x_E, y_E of a "
    "right-handed E with +z out of the gel; no mirroring applied.";
const char* const kImportPoseNote =
    "Pose unknown (pose_known false): poses.csv holds identity placeholder rows only so that every sample "
    "has one row per frame; they are not measurements. The sample's indenter 'unknown_contact' is a labelled "
    "1 mm sphere proxy (tsd/1 requires a mesh), not the real contact.";

std::string track_summary(const TrackResult& r) {
  std::ostringstream o;
  o << r.frames() << " frames, " << r.markers() << " markers";
  if (r.grid_rows)
    o << " (grid " << r.grid_rows << " rows x " << r.grid_cols << " cols)";
  else
    o << " (irregular grid at rest)";
  o << ", pitch " << format_number(r.pitch_px, "%.2f") << " px, lost " << format_number(r.lost_fraction(), "%.4f")
    << " of marker-frames";
  return o.str();
}

void require_input_dir(const std::string& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, "input directory not found");
}

TsdDatasetOut dataset_from_track(const TrackResult& track, const std::string& name, const std::string& sample_id,
                                 double dt_s, double mm_per_px, const std::string& source_note) {
  TsdDatasetOut ds;
  ds.name = name;
  ds.kind = "real";
  ds.mm_per_px = mm_per_px;
  if (track.image_width > 0) {
    ds.width_px = track.image_width;
    ds.height_px = track.image_height;
  }
  ds.principal_px = Vec2((ds.width_px - 1) / 2.0, (ds.height_px - 1) / 2.0);
  ds.markers_rest_px = track.rest_px;
  // tsd/1 readers require every sample to name a listed indenter with a mesh: unknown contacts get a
  // clearly labelled proxy (a 1 mm sphere), never to be used as the real geometry.
  ds.indenters = {{kUnknownContact,
                   {{"mesh", "meshes/unknown_contact.obj"},
                    {"proxy",
                     "contact geometry unknown (fingertip, grasped object or unmodelled indenter); "
                     "this 1 mm sphere only satisfies the format"}}}};
  ds.mesh_files = {{"meshes/unknown_contact.obj", sphere_obj(0.001)}};
  TsdSampleOut s;
  s.id = sample_id;
  s.indenter = kUnknownContact;
  s.dt_s = dt_s;
  s.disp_px = track.disp_px;
  s.X_EI.assign(track.disp_px.size(), Pose::Identity());
  ds.samples.push_back(std::move(s));
  ds.provenance = source_note;
  return ds;
}

}  // namespace sb
