#include "core/tracking/track_eval.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "core/base/error.hpp"
#include "core/base/median.hpp"
#include "core/base/numbers.hpp"

namespace sb {
namespace {

// A tracked marker pairs with a reference marker when their rest positions are this close (pixels).
constexpr double kPairingRadiusPx = 8.0;

// Reference marker -> tracked marker (-1 none), nearest rest position within kPairingRadiusPx.
std::vector<int> pair_by_rest(const std::vector<Vec2>& tracked_rest, const std::vector<Vec2>& ref_rest) {
  std::vector<int> out(ref_rest.size(), -1);
  for (std::size_t r = 0; r < ref_rest.size(); ++r) {
    double best = kPairingRadiusPx;
    for (std::size_t t = 0; t < tracked_rest.size(); ++t) {
      const double d = (tracked_rest[t] - ref_rest[r]).norm();
      if (d < best) best = d, out[r] = static_cast<int>(t);
    }
  }
  return out;
}

struct Stats {
  double rmse = kNaN, median = kNaN, p95 = kNaN, max = 0;
};
Stats stats_of(const std::vector<double>& errors) {
  Stats s;
  double s2 = 0;
  for (double e : errors) s2 += e * e, s.max = std::max(s.max, e);
  if (!errors.empty()) s.rmse = std::sqrt(s2 / double(errors.size()));
  s.median = percentile_interpolated(errors, 0.5);
  s.p95 = percentile_interpolated(errors, 0.95);
  return s;
}

void summarise(const std::vector<double>& errors, const std::vector<double>& disp_errors, TrackComparison& c) {
  c.pairs = static_cast<int>(errors.size());
  const Stats p = stats_of(errors), d = stats_of(disp_errors);
  c.rmse_px = p.rmse, c.median_px = p.median, c.p95_px = p.p95, c.max_px = p.max;
  c.disp_rmse_px = d.rmse, c.disp_median_px = d.median, c.disp_p95_px = d.p95, c.disp_max_px = d.max;
}

}  // namespace

VendorTrack read_vendor_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open vendor marker CSV");
  struct Row {
    int frame, row, col;
    double x0, y0, x, y;
  };
  std::vector<Row> rows;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    Row r;
    if (!(ss >> r.frame >> r.row >> r.col >> r.x0 >> r.y0 >> r.x >> r.y))
      throw InputError(path, lineno, 1, "expected 7 numbers: frame, row, col, x0, y0, x, y");
    if (r.frame < 1 || r.row < 0 || r.col < 0) throw InputError(path, lineno, 1, "negative index or frame < 1");
    rows.push_back(r);
  }
  if (rows.empty()) throw InputError(path, "no rows");
  int max_row = 0, max_col = 0, max_frame = 0;
  for (const auto& r : rows)
    max_row = std::max(max_row, r.row), max_col = std::max(max_col, r.col), max_frame = std::max(max_frame, r.frame);
  const int cols = max_col + 1, n = (max_row + 1) * cols;
  VendorTrack v;
  v.frames = max_frame;
  v.rest_px.assign(n, Vec2(kNaN, kNaN));
  v.position_px.assign(max_frame, std::vector<Vec2>(n, Vec2(kNaN, kNaN)));
  for (const auto& r : rows) {
    const int m = r.row * cols + r.col;
    if (!v.rest_px[m].allFinite()) v.rest_px[m] = Vec2(r.x0, r.y0);
    v.position_px[r.frame - 1][m] = Vec2(r.x, r.y);
  }
  return v;
}

TrackComparison compare_to_vendor(const TrackResult& tracked, const VendorTrack& vendor, int frame_offset) {
  TrackComparison c;
  c.reference_markers = static_cast<int>(vendor.rest_px.size());
  // Pair on the first frame's positions (vendor x0, y0 and our frame-0 positions) so a rest-median
  // difference does not decide the pairing.
  const auto pairing = pair_by_rest(tracked.rest_px, vendor.rest_px);
  std::vector<double> errors, disp_errors;
  Vec2 offset = Vec2::Zero();
  for (std::size_t r = 0; r < pairing.size(); ++r) {
    if (pairing[r] < 0) continue;
    ++c.paired_markers;
    offset += tracked.rest_px[pairing[r]] - vendor.rest_px[r];
  }
  if (c.paired_markers) c.mean_rest_offset_px = offset / c.paired_markers;
  for (int f = 0; f < vendor.frames; ++f) {
    const int tf = f + frame_offset;
    if (tf < 0 || tf >= tracked.frames()) continue;
    for (std::size_t r = 0; r < pairing.size(); ++r) {
      const Vec2& ref = vendor.position_px[f][r];
      if (pairing[r] < 0 || !ref.allFinite()) continue;
      const Vec2& d = tracked.disp_px[tf][pairing[r]];
      if (!d.allFinite()) {
        ++c.lost;
        continue;
      }
      errors.push_back((tracked.rest_px[pairing[r]] + d - ref).norm());
      disp_errors.push_back((d - (ref - vendor.rest_px[r])).norm());
    }
  }
  summarise(errors, disp_errors, c);
  return c;
}

std::vector<std::vector<Vec2>> read_markers_csv(const std::string& path, int markers) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open markers.csv");
  std::string line;
  std::getline(in, line);
  if (line.rfind("frame,marker,du_px,dv_px", 0) != 0)
    throw InputError(path, 1, 1, "expected header frame,marker,du_px,dv_px");
  std::vector<std::vector<Vec2>> out;
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line == "\r") continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    long frame, marker;
    std::string du, dv;
    if (!(ss >> frame >> marker >> du >> dv)) throw InputError(path, lineno, 1, "expected 4 fields");
    if (frame < 0 || marker < 0 || marker >= markers)
      throw InputError(path, lineno, 1, "marker index outside markers_rest_px");
    if (static_cast<long>(out.size()) <= frame) out.resize(frame + 1, std::vector<Vec2>(markers, Vec2(kNaN, kNaN)));
    try {
      out[frame][marker] = Vec2(std::stod(du), std::stod(dv));
    } catch (const std::exception&) {
      throw InputError(path, lineno, 1, "not a number");
    }
  }
  return out;
}

TrackComparison compare_to_reference(const TrackResult& tracked, const std::vector<Vec2>& ref_rest,
                                     const std::vector<std::vector<Vec2>>& ref_disp, bool remove_rest_offset) {
  TrackComparison c;
  c.reference_markers = static_cast<int>(ref_rest.size());
  const auto pairing = pair_by_rest(tracked.rest_px, ref_rest);
  Vec2 offset = Vec2::Zero();
  for (std::size_t r = 0; r < pairing.size(); ++r)
    if (pairing[r] >= 0) ++c.paired_markers, offset += tracked.rest_px[pairing[r]] - ref_rest[r];
  if (c.paired_markers) c.mean_rest_offset_px = offset / c.paired_markers;
  std::vector<double> errors, disp_errors;
  const int frames = std::min<int>(tracked.frames(), static_cast<int>(ref_disp.size()));
  for (int f = 0; f < frames; ++f)
    for (std::size_t r = 0; r < pairing.size(); ++r) {
      if (pairing[r] < 0 || !ref_disp[f][r].allFinite()) continue;
      const Vec2& d = tracked.disp_px[f][pairing[r]];
      if (!d.allFinite()) {
        ++c.lost;
        continue;
      }
      const Vec2 tracked_pos = (remove_rest_offset ? Vec2::Zero() : tracked.rest_px[pairing[r]]) + d;
      const Vec2 ref_pos = (remove_rest_offset ? Vec2::Zero() : ref_rest[r]) + ref_disp[f][r];
      errors.push_back((tracked_pos - ref_pos).norm());
      disp_errors.push_back((d - ref_disp[f][r]).norm());
    }
  summarise(errors, disp_errors, c);
  return c;
}

}  // namespace sb
