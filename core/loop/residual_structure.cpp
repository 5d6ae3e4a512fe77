// The residual's structure against physical covariates (residual_structure.hpp).
#include "core/loop/residual_structure.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "core/base/format.hpp"
#include "core/base/numbers.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/loop_samples.hpp"

namespace sb {

namespace {

struct Point {  // one scored marker-frame and its covariates
  double err_px;
  double t_contact_s, radial_px, d_centre_mm, d_edge_mm, depth_mm, travel_mm;
  LoadingState loading;
  // In the contact's own frame (in contact only): the marker's distance outside the contact edge (mm,
  // < 0 inside), the residual along the outward direction and along the travel (px), the side
  // (+1 leading: ahead of the centre along the travel, -1 trailing, 0 no travel yet) and the phase.
  double contact_edge_mm = 0, radial_res_px = 0, along_res_px = 0;
  int side = 0;
  ContactPhase phase = ContactPhase::kNoContact;
};

CovariateTable numeric_table(const std::string& name, const std::string& unit, const std::vector<Point>& pts,
                             double Point::*field, int bins) {
  CovariateTable t;
  t.name = name, t.unit = unit;
  if (pts.empty()) return t;
  const auto [lo_it, hi_it] = std::minmax_element(
      pts.begin(), pts.end(), [field](const Point& a, const Point& b) { return a.*field < b.*field; });
  const double lo = (*lo_it).*field;
  const double hi = std::max((*hi_it).*field, lo + 1e-9);
  std::vector<double> sum(bins, 0.0);
  std::vector<long> n(bins, 0);
  for (const auto& p : pts) {
    const int b = std::clamp(static_cast<int>((p.*field - lo) / (hi - lo) * bins), 0, bins - 1);
    sum[b] += p.err_px * p.err_px;
    ++n[b];
  }
  for (int b = 0; b < bins; ++b) {
    const double a = lo + (hi - lo) * b / bins, c = lo + (hi - lo) * (b + 1) / bins;
    t.labels.push_back(format_number(a, "%.3g") + "-" + format_number(c, "%.3g"));
    t.centre.push_back(0.5 * (a + c));
    t.rms_px.push_back(n[b] ? std::sqrt(sum[b] / n[b]) : kNaN);
    t.count.push_back(n[b]);
  }
  return t;
}

CovariateTable loading_table(const std::vector<Point>& pts) {
  CovariateTable t;
  t.name = "loading state";
  t.labels = {"loading", "held", "unloading", "no contact"};
  t.centre = {0, 1, 2, 3};
  std::vector<double> sum(4, 0.0);
  std::vector<long> n(4, 0);
  for (const auto& p : pts) {
    sum[static_cast<int>(p.loading)] += p.err_px * p.err_px;
    ++n[static_cast<int>(p.loading)];
  }
  for (int b = 0; b < 4; ++b) {
    t.rms_px.push_back(n[b] ? std::sqrt(sum[b] / n[b]) : kNaN);
    t.count.push_back(n[b]);
  }
  return t;
}

// A contact-frame table: RMS and mean radial / along-travel residual per bin of the points in contact
// that `bin_of` places (-1: not in this table).
CovariateTable contact_table(const std::string& name, const std::string& unit, std::vector<std::string> labels,
                             const std::vector<Point>& pts, const std::function<int(const Point&)>& bin_of) {
  const int n_bins = static_cast<int>(labels.size());
  CovariateTable t;
  t.name = name, t.unit = unit, t.labels = std::move(labels);
  t.contact_frame = true;
  std::vector<double> sq(n_bins, 0.0), radial(n_bins, 0.0), along(n_bins, 0.0);
  std::vector<long> n(n_bins, 0);
  for (const auto& p : pts) {
    const int b = p.phase == ContactPhase::kNoContact ? -1 : bin_of(p);
    if (b < 0) continue;
    sq[b] += p.err_px * p.err_px, radial[b] += p.radial_res_px, along[b] += p.along_res_px;
    ++n[b];
  }
  for (int b = 0; b < n_bins; ++b) {
    t.centre.push_back(b);
    t.rms_px.push_back(n[b] ? std::sqrt(sq[b] / n[b]) : kNaN);
    t.mean_radial_px.push_back(n[b] ? radial[b] / n[b] : kNaN);
    t.mean_along_px.push_back(n[b] ? along[b] / n[b] : kNaN);
    t.count.push_back(n[b]);
  }
  return t;
}

// Labels of the bins that fixed edges make: "< e0", "e0 to e1", ..., "> en".
std::vector<std::string> edge_labels(const std::vector<double>& edges) {
  std::vector<std::string> labels = {"< " + format_number(edges.front(), "%g")};
  for (std::size_t b = 0; b + 1 < edges.size(); ++b)
    labels.push_back(format_number(edges[b], "%g") + " to " + format_number(edges[b + 1], "%g"));
  labels.push_back("> " + format_number(edges.back(), "%g"));
  return labels;
}

int edge_bin(const std::vector<double>& edges, double v) {
  return static_cast<int>(std::upper_bound(edges.begin(), edges.end(), v) - edges.begin());
}

// Distance outside the contact edge (mm), on one side of the contact along the travel: fixed bins so
// that reports of different datasets line up.
CovariateTable contact_edge_table(const std::vector<Point>& pts, int side) {
  static const std::vector<double> kEdgesMm = {-4, -2, -1, 0, 1, 2, 4, 8};
  const char* which = side > 0 ? "leading" : side < 0 ? "trailing" : "no travel";
  return contact_table(std::string("contact frame: distance outside the contact edge, ") + which + " side", "mm",
                       edge_labels(kEdgesMm), pts,
                       [side](const Point& p) { return p.side == side ? edge_bin(kEdgesMm, p.contact_edge_mm) : -1; });
}

CovariateTable contact_phase_table(const std::vector<Point>& pts) {
  return contact_table("contact frame: phase", "", {"loading", "hold", "slide", "unloading"}, pts,
                       [](const Point& p) { return static_cast<int>(p.phase); });
}

// Normal load as penetration depth, in contact only, with the mean radial part (dilation error vs load).
CovariateTable contact_load_table(const std::vector<Point>& pts) {
  static const std::vector<double> kEdgesMm = {0.25, 0.5, 0.75, 1.0, 1.5};
  return contact_table("contact frame: normal load (penetration depth)", "mm", edge_labels(kEdgesMm), pts,
                       [](const Point& p) { return edge_bin(kEdgesMm, p.depth_mm); });
}

// Per-frame contact description of one sample: depth, contact centre and radius, loading state, phase,
// time since first contact and tangential travel since first contact (length and unit direction).
struct FrameContact {
  std::vector<double> depth_m, radius_m, t_contact_s, travel_m;
  std::vector<Vec2> centre_E, travel_dir_E;
  std::vector<Vec2> tilt_E;  // xy of the indenter's approach axis (R_EI z): its length is the tilt's sine
  std::vector<LoadingState> loading;
  std::vector<ContactPhase> phase;
};

LoadingState loading_state(const Penetration& now, double previous_depth_m) {
  if (!now.penetrating) return LoadingState::kNoContact;
  if (now.depth_m > previous_depth_m + kHeldStillM) return LoadingState::kLoading;
  if (now.depth_m < previous_depth_m - kHeldStillM) return LoadingState::kUnloading;
  return LoadingState::kDepthHeld;
}

ContactPhase contact_phase(LoadingState load, bool moved) {
  switch (load) {
    case LoadingState::kNoContact: return ContactPhase::kNoContact;
    case LoadingState::kLoading: return ContactPhase::kLoading;
    case LoadingState::kUnloading: return ContactPhase::kUnloading;
    case LoadingState::kDepthHeld: return moved ? ContactPhase::kSlide : ContactPhase::kStill;
  }
  return ContactPhase::kNoContact;
}

FrameContact frame_contacts(const Sensor& sensor, const FitSample& s) {
  FrameContact c;
  const std::size_t F = s.X_EI.size();
  int first = -1;
  for (std::size_t k = 0; k < F; ++k) {
    const Penetration p = indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]);
    c.depth_m.push_back(p.depth_m);
    c.radius_m.push_back(p.radius_m);
    c.centre_E.push_back(p.centre_E);
    c.tilt_E.push_back((s.X_EI[k].linear() * Vec3::UnitZ()).head<2>());
    if (first < 0 && p.penetrating) first = static_cast<int>(k);
    c.loading.push_back(loading_state(p, k ? c.depth_m[k - 1] : 0.0));
    c.phase.push_back(contact_phase(c.loading.back(), k && !held_still(s.X_EI[k - 1], s.X_EI[k])));
  }
  for (std::size_t k = 0; k < F; ++k) {
    const bool after = first >= 0 && static_cast<int>(k) >= first;
    c.t_contact_s.push_back(after ? (k - first) * s.dt_s : 0.0);
    const Vec2 travel = after ? Vec2((s.X_EI[k].translation() - s.X_EI[first].translation()).head<2>()) : Vec2::Zero();
    c.travel_m.push_back(travel.norm());
    c.travel_dir_E.push_back(travel.norm() > kHeldStillM ? Vec2(travel.normalized()) : Vec2::Zero());
  }
  return c;
}

// The covariates of residual `e` of marker j at frame k.
Point marker_point(const Sensor& sensor, const FrameContact& fc, std::size_t k, std::size_t j, const Vec2& e) {
  const Vec2 p = sensor.p_EM[j].head<2>();
  const Vec2 half = 0.5 * sensor.gel.size_m;
  const double edge = std::max(0.0, std::min(half.x() - std::abs(p.x()), half.y() - std::abs(p.y())));
  Point pt{e.norm(),
           fc.t_contact_s[k],
           (sensor.markers_rest_px[j] - sensor.camera.principal_px).norm(),
           1e3 * (p - fc.centre_E[k]).norm(),
           1e3 * edge,
           1e3 * fc.depth_m[k],
           1e3 * fc.travel_m[k],
           fc.loading[k]};
  // The image axes are the E axes scaled (Camera::px_from_E), so E directions apply to px residuals.
  const Vec2 out_E = p - fc.centre_E[k];
  const Vec2 dir_E = fc.travel_dir_E[k];
  pt.phase = fc.phase[k];
  pt.contact_edge_mm = 1e3 * (out_E.norm() - fc.radius_m[k]);
  pt.radial_res_px = out_E.norm() > 0 ? e.dot(out_E.normalized()) : 0.0;
  pt.along_res_px = e.dot(dir_E);
  pt.side = dir_E.isZero() ? 0 : out_E.dot(dir_E) >= 0 ? 1 : -1;
  return pt;
}

// A scored frame's covariates for the binned mean fields.
struct FrameKey {
  bool in_contact = false;
  double depth_mm = 0;
  Vec2 travel_dir_E = Vec2::Zero(), tilt_E = Vec2::Zero();
};

// One sample's scored marker-frames (points) and its scored frames as rows of 2M residual components.
struct SampleResidual {
  std::vector<Point> points;
  std::vector<Eigen::VectorXd> rows;
  std::vector<FrameKey> keys;  // per row
};

SampleResidual sample_residual(const std::string& model_id, const ParamSet& params,
                               const std::shared_ptr<const Sensor>& sensor, const FitSample& s) {
  auto model = make_spec_model(model_id, sensor, s.indenter);
  model->set_params(params);
  const auto pred = simulate_sample(*model, s);
  const FrameContact fc = frame_contacts(*sensor, s);
  const int M = static_cast<int>(sensor->markers_rest_px.size());
  SampleResidual out;
  int last_frame = -1;
  for (int f : active_marker_frames(s.meas_px)) {
    const int k = f / M, j = f % M;
    if (k != last_frame) {
      out.rows.push_back(Eigen::VectorXd::Zero(2 * Eigen::Index{M}));
      out.keys.push_back({fc.depth_m[k] > 0, 1e3 * fc.depth_m[k], fc.travel_dir_E[k], fc.tilt_E[k]});
      last_frame = k;
    }
    const Vec2 e = s.meas_px[k][j] - pred[k][j];
    out.rows.back().segment<2>(2 * Eigen::Index{j}) = e;
    out.points.push_back(marker_point(*sensor, fc, k, j, e));
  }
  return out;
}

std::vector<CovariateTable> covariate_tables(const std::vector<Point>& all, int bins) {
  std::vector<CovariateTable> t;
  t.push_back(numeric_table("time since contact", "s", all, &Point::t_contact_s, bins));
  t.push_back(loading_table(all));
  t.push_back(numeric_table("radial distance from principal point", "px", all, &Point::radial_px, bins));
  t.push_back(numeric_table("distance from contact centre", "mm", all, &Point::d_centre_mm, bins));
  t.push_back(numeric_table("distance from gel edge", "mm", all, &Point::d_edge_mm, bins));
  t.push_back(numeric_table("penetration depth", "mm", all, &Point::depth_mm, bins));
  t.push_back(numeric_table("tangential travel", "mm", all, &Point::travel_mm, bins));
  for (int side : {1, -1, 0}) t.push_back(contact_edge_table(all, side));
  t.push_back(contact_phase_table(all));
  t.push_back(contact_load_table(all));
  return t;
}

// The direction bins: 0 none (below `none_below`), then the nearest of +x, +y, -x, -y.
int direction_bin(const Vec2& v, double none_below) {
  if (v.norm() < none_below) return 0;
  if (std::abs(v.x()) >= std::abs(v.y())) return v.x() > 0 ? 1 : 3;
  return v.y() > 0 ? 2 : 4;
}

// Means of the rows whose bin (bin_of, -1: none) is each of `labels`.
BinnedMeanFields mean_per_bin(std::string name, std::vector<std::string> labels,
                              const std::vector<Eigen::VectorXd>& rows, const std::function<int(std::size_t)>& bin_of,
                              std::size_t M) {
  BinnedMeanFields b;
  b.name = std::move(name);
  b.labels = std::move(labels);
  const std::size_t B = b.labels.size();
  std::vector<Eigen::VectorXd> sum(B, Eigen::VectorXd::Zero(2 * M));
  b.frames.assign(B, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int k = bin_of(r);
    if (k < 0) continue;
    sum[k] += rows[r];
    ++b.frames[k];
  }
  b.mean_px.assign(B, std::vector<Vec2>(M, Vec2::Zero()));
  for (std::size_t k = 0; k < B; ++k)
    for (std::size_t j = 0; b.frames[k] > 0 && j < M; ++j)
      b.mean_px[k][j] = Vec2(sum[k](2 * j), sum[k](2 * j + 1)) / double(b.frames[k]);
  return b;
}

std::vector<BinnedMeanFields> binned_mean_fields(const std::vector<Eigen::VectorXd>& rows,
                                                 const std::vector<FrameKey>& keys, std::size_t M, int bins) {
  constexpr double kTiltNoneSin = 0.0349;  // sin 2 deg: below it, untilted
  const std::vector<std::string> directions = {"none", "+x (+u)", "+y (+v)", "-x (-u)", "-y (-v)"};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& k : keys)
    if (k.in_contact) lo = std::min(lo, k.depth_mm), hi = std::max(hi, k.depth_mm);
  hi = std::max(hi, lo + 1e-9);
  std::vector<std::string> depth_labels;
  for (int b = 0; b < bins && std::isfinite(lo); ++b)
    depth_labels.push_back(format_number(lo + (hi - lo) * b / bins, "%.3g") + "-" +
                           format_number(lo + (hi - lo) * (b + 1) / bins, "%.3g"));
  const auto depth_bin = [&](std::size_t r) {
    if (!keys[r].in_contact) return -1;
    return std::clamp(static_cast<int>((keys[r].depth_mm - lo) / (hi - lo) * bins), 0, bins - 1);
  };
  const auto travel_bin = [&](std::size_t r) {
    return keys[r].in_contact ? direction_bin(keys[r].travel_dir_E, 0.5) : -1;
  };
  const auto tilt_bin = [&](std::size_t r) {
    return keys[r].in_contact ? direction_bin(keys[r].tilt_E, kTiltNoneSin) : -1;
  };
  return {mean_per_bin("penetration depth (mm)", depth_labels, rows, depth_bin, M),
          mean_per_bin("travel direction", directions, rows, travel_bin, M),
          mean_per_bin("tilt direction", directions, rows, tilt_bin, M)};
}

// The mean field, the explained variance of the first three principal components of the centred rows
// and the first component (scaled to its RMS amplitude; it points along the mean field where it can, else
// its largest entry is > 0).
void principal_components(const std::vector<Eigen::VectorXd>& rows, std::size_t M, ResidualStructure* out) {
  out->mean_field_px.assign(M, Vec2::Zero());
  out->pc1_px.assign(M, Vec2::Zero());
  if (rows.empty()) return;
  Eigen::MatrixXd R(rows.size(), 2 * M);
  for (std::size_t r = 0; r < rows.size(); ++r) R.row(r) = rows[r].transpose();
  const Eigen::RowVectorXd mean = R.colwise().mean();
  for (std::size_t j = 0; j < M; ++j) out->mean_field_px[j] = Vec2(mean(2 * j), mean(2 * j + 1));
  R.rowwise() -= mean;
  Eigen::BDCSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeThinV);
  const Eigen::VectorXd s2 = svd.singularValues().array().square();
  const double total = s2.sum();
  for (int c = 0; c < 3; ++c) out->explained_variance.push_back(c < s2.size() && total > 0 ? s2(c) / total : 0.0);
  if (svd.singularValues().size() == 0) return;
  Eigen::VectorXd v = svd.matrixV().col(0) * svd.singularValues()(0) / std::sqrt(double(R.rows()));
  const double dot = v.dot(mean.transpose());
  Eigen::Index imax = 0;
  v.cwiseAbs().maxCoeff(&imax);
  if (dot < 0 || (dot == 0 && v(imax) < 0)) v = -v;
  for (std::size_t j = 0; j < M; ++j) out->pc1_px[j] = Vec2(v(2 * j), v(2 * j + 1));
}

}  // namespace

FieldSummary summarise_field(const std::vector<Vec2>& field_px) {
  FieldSummary f;
  if (field_px.empty()) return f;
  double ss = 0;
  for (const Vec2& v : field_px)
    ss += v.squaredNorm(), f.longest_px = std::max(f.longest_px, v.norm()), f.shift_px += v;
  f.rms_px = std::sqrt(ss / double(field_px.size()));
  f.shift_px /= double(field_px.size());
  return f;
}

ResidualStructure analyse_residual(const std::string& model_id, const ParamSet& params,
                                   std::shared_ptr<const Sensor> sensor, const std::vector<FitSample>& samples,
                                   int bins) {
  std::vector<const FitSample*> pointers;
  pointers.reserve(samples.size());
  for (const FitSample& s : samples) pointers.push_back(&s);
  return analyse_residual(model_id, params, std::move(sensor), pointers, bins);
}

ResidualStructure analyse_residual(const std::string& model_id, const ParamSet& params,
                                   std::shared_ptr<const Sensor> sensor, const std::vector<const FitSample*>& samples,
                                   int bins) {
  std::vector<SampleResidual> per_sample(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()),
                    [&](int i) { per_sample[i] = sample_residual(model_id, params, sensor, *samples[i]); });
  std::vector<Point> all;
  std::vector<Eigen::VectorXd> rows;
  std::vector<FrameKey> keys;
  for (auto& s : per_sample) {
    all.insert(all.end(), s.points.begin(), s.points.end());
    keys.insert(keys.end(), s.keys.begin(), s.keys.end());
    rows.insert(rows.end(), std::make_move_iterator(s.rows.begin()), std::make_move_iterator(s.rows.end()));
  }
  ResidualStructure out;
  double sse = 0;
  for (const auto& p : all) sse += p.err_px * p.err_px;
  out.marker_frames = static_cast<long>(all.size());
  out.frames = static_cast<long>(rows.size());
  out.rmse_px = all.empty() ? kNaN : std::sqrt(sse / all.size());
  out.covariates = covariate_tables(all, bins);
  principal_components(rows, sensor->markers_rest_px.size(), &out);
  out.binned_fields = binned_mean_fields(rows, keys, sensor->markers_rest_px.size(), std::max(1, bins / 2));
  return out;
}

}  // namespace sb
