#include "core/importers.hpp"

namespace sb {

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
  TsdSampleOut s;
  s.id = sample_id;
  s.dt_s = dt_s;
  s.disp_px = track.disp_px;
  s.X_EI.assign(track.disp_px.size(), Pose::Identity());
  ds.samples.push_back(std::move(s));
  ds.provenance = source_note;
  return ds;
}

}  // namespace sb
