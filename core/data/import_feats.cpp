// The FEATS sample importer (import_feats.hpp).
#include "core/data/import_feats.hpp"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "core/base/error.hpp"
#include "core/base/format.hpp"

namespace fs = std::filesystem;

namespace sb {

ImportReport import_feats(const std::string& in_dir, const std::string& out_dir) {
  require_input_dir(in_dir);
  const std::string nocontact_path = (fs::path(in_dir) / "nocontact.png").string();
  const std::string contact_path = (fs::path(in_dir) / "cuboid_10mm_contact.png").string();
  std::vector<cv::Mat> frames;
  for (const auto& p : {nocontact_path, contact_path}) {
    cv::Mat img = cv::imread(p, cv::IMREAD_COLOR);  // drops the contact frame's alpha channel
    if (img.empty()) throw InputError(p, "cannot read image");
    frames.push_back(img);
  }
  if (frames[0].size() != frames[1].size()) throw InputError(contact_path, "size differs from nocontact.png");
  TrackerOptions opts;
  opts.rest_frames = 1;  // the no-contact frame is the rest
  opts.grid_rows = 7;
  opts.grid_cols = 9;
  const TrackResult r = track_frames(frames, opts);
  // point_correspondences.yaml: 10 mm = 140 px.
  constexpr double kMmPerPx = 10.0 / 140.0;
  std::string prov =
      "FEATS sample from feats-ai/feats (MIT), see raw/feats/SOURCE.md: frame 0 = nocontact.png (rest), frame 1 = "
      "cuboid_10mm_contact.png (alpha dropped), a 10 mm cuboid pressed into a GelSight Mini. Markers tracked by "
      "shearbench's tracker (rest = frame 0, expected grid 7 rows x 9 cols): " +
      track_summary(r) + ". The real indenter is a 10 mm cuboid; its pose is unknown. Scale " +
      format_number(kMmPerPx, "%.4f") +
      " mm/px from the authors' point_correspondences.yaml (10 mm = 140 px); "
      "their world axes are rotated 90 degrees against the image, we keep image axes. " +
      kImportAxisNote + " " + kImportPoseNote +
      " The gel is domed (4.0 mm at the centre, 2.75 mm at the edge); written as flat 4.0 mm here.";
  for (const auto& w : r.warnings) prov += " Tracker warning: " + w + ".";
  TsdDatasetOut ds = dataset_from_track(r, "feats_cuboid", "cuboid_contact", 1.0, kMmPerPx, prov);
  ds.license = "MIT";
  ds.gel_thickness_m = 0.004;
  ds.samples.front().frames = frames;
  write_tsd_dataset(ds, out_dir);
  ImportReport report;
  report.datasets.push_back(out_dir);
  report.lines.push_back("feats: " + track_summary(r));
  return report;
}

}  // namespace sb
