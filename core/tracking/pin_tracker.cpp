#include "core/tracking/pin_tracker.hpp"
#include "core/base/median.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/base/error.hpp"
#include "core/base/numbers.hpp"

namespace sb {
namespace {

constexpr double kNeighbourRadius = 1.6;  // pitches: the first ring of a hexagonal lattice

Vec2 median2(const std::vector<Vec2>& v) {
  std::vector<double> x, y;
  for (const auto& p : v) {
    x.push_back(p.x());
    y.push_back(p.y());
  }
  return Vec2(median(x), median(y));
}

cv::Mat grey_of(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat g;
  cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
  return g;
}

struct Blob {
  Vec2 uv;
  double area, fill, aspect;
};

std::vector<Blob> blobs_of(const cv::Mat& image, int threshold) {
  cv::Mat bin, labels, stats, centroids;
  cv::threshold(grey_of(image), bin, threshold, 255, cv::THRESH_BINARY);
  const int n = cv::connectedComponentsWithStats(bin, labels, stats, centroids, 8, CV_32S);
  std::vector<Blob> out;
  for (int i = 1; i < n; ++i) {  // 0 = background
    const double w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    const double area = stats.at<int>(i, cv::CC_STAT_AREA);
    out.push_back({Vec2(centroids.at<double>(i, 0), centroids.at<double>(i, 1)), area, area / (w * h),
                   std::max(w, h) / std::min(w, h)});
  }
  return out;
}

// Index of the nearest of `pts` to q (and its squared distance); -1 when pts is empty. Entries with NaN
// are skipped.
std::pair<int, double> nearest(const std::vector<Vec2>& pts, const Vec2& q) {
  int best = -1;
  double d2 = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < pts.size(); ++j) {
    const double d = (pts[j] - q).squaredNorm();
    if (d < d2) {
      d2 = d;
      best = static_cast<int>(j);
    }
  }
  return {best, d2};
}

// match[i] = detection of prediction i when they are mutual nearest neighbours within `gate`, else -1.
std::vector<int> mutual_nearest(const std::vector<Vec2>& pred, const std::vector<Vec2>& det, double gate) {
  std::vector<int> match(pred.size(), -1);
  std::vector<int> det_to_pred(det.size(), -1);
  for (std::size_t j = 0; j < det.size(); ++j) det_to_pred[j] = nearest(pred, det[j]).first;
  for (std::size_t i = 0; i < pred.size(); ++i) {
    if (!pred[i].allFinite()) continue;
    const auto [j, d2] = nearest(det, pred[i]);
    if (j >= 0 && d2 <= gate * gate && det_to_pred[j] == static_cast<int>(i)) match[i] = j;
  }
  return match;
}

// Global affine start -> image from mutual nearest neighbours, refined a few times (start = rest + prior).
std::vector<Vec2> global_prediction(const std::vector<Vec2>& start, const std::vector<Vec2>& det, double gate,
                                    double pitch) {
  std::vector<Vec2> pred = start;
  for (int it = 0; it < 4; ++it) {
    const std::vector<int> m = mutual_nearest(pred, det, gate);
    std::vector<cv::Point2f> from, to;
    for (std::size_t i = 0; i < m.size(); ++i)
      if (m[i] >= 0) {
        from.emplace_back(float(start[i].x()), float(start[i].y()));
        to.emplace_back(float(det[m[i]].x()), float(det[m[i]].y()));
      }
    if (from.size() < 6) break;
    const cv::Mat A = cv::estimateAffine2D(from, to, cv::noArray(), cv::RANSAC, 0.25 * pitch);
    if (A.empty()) break;
    for (std::size_t i = 0; i < pred.size(); ++i) {
      const Vec2& r = start[i];
      pred[i] = Vec2(A.at<double>(0, 0) * r.x() + A.at<double>(0, 1) * r.y() + A.at<double>(0, 2),
                     A.at<double>(1, 0) * r.x() + A.at<double>(1, 1) * r.y() + A.at<double>(1, 2));
    }
  }
  return pred;
}

std::vector<std::vector<int>> neighbours_within(const std::vector<Vec2>& pts, double radius) {
  std::vector<std::vector<int>> nb(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (i != j && (pts[i] - pts[j]).norm() <= radius) nb[i].push_back(static_cast<int>(j));
  return nb;
}

constexpr double kSeedFraction = 0.2;   // pitches: seed matches must sit this close to the global fit
constexpr double kSupportRadius = 2.2;  // pitches: matched pins that predict a neighbour (local affine field)

// Prediction of pin i from the residual field res = disp - prior of its matched surroundings:
// rest + prior + the median residual of its matched first ring, or (affine) + the least-squares affine
// field r(x) = r0 + G (x - x_i) of the matched pins within kSupportRadius pitches (their mean with fewer
// than four). The prior carries the large, known part of the field, so what is interpolated between
// neighbours is only what the prior misses. nullopt when fewer than `need` matched pins are in the first ring.
std::optional<Vec2> local_prediction(const PinReference& ref, const std::vector<Vec2>& prior,
                                     const std::vector<Vec2>& res, std::size_t i, int need, bool affine) {
  int ring = 0;
  for (int j : ref.neighbours[i]) ring += res[j].allFinite();
  if (ring < need) return std::nullopt;
  const Vec2 base = ref.rest_px[i] + prior[i];
  if (!affine) {
    std::vector<Vec2> ring_res;
    for (int j : ref.neighbours[i])
      if (res[j].allFinite()) ring_res.push_back(res[j]);
    return base + median2(ring_res);
  }
  const double r2 = std::pow(kSupportRadius * ref.pitch_px, 2);
  std::vector<std::size_t> support;
  for (std::size_t j = 0; j < res.size(); ++j)
    if (j != i && res[j].allFinite() && (ref.rest_px[j] - ref.rest_px[i]).squaredNorm() <= r2) support.push_back(j);
  Vec2 mean = Vec2::Zero();
  for (std::size_t j : support) mean += res[j];
  mean /= double(support.size());
  if (support.size() < 4) return base + mean;
  Eigen::MatrixXd A(support.size(), 3), b(support.size(), 2);
  for (std::size_t k = 0; k < support.size(); ++k) {
    const Vec2 r = (ref.rest_px[support[k]] - ref.rest_px[i]) / ref.pitch_px;
    A.row(k) << 1.0, r.x(), r.y();
    b.row(k) = res[support[k]].transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  if (svd.singularValues()(2) < 1e-3 * svd.singularValues()(0)) return base + mean;  // collinear
  const Eigen::MatrixXd x = svd.solve(b);
  return base + Vec2(x(0, 0), x(0, 1));
}

}  // namespace

ParamSet pin_tracker_param_specs() {
  const PinTrackerOptions d;
  return ParamSet({
      {"threshold", "grey", double(d.threshold), 1, 254, "grey level separating pins from background"},
      {"min_area_factor", "", d.min_area_factor, 0.05, 1, "smaller blobs (x reference median area) are dropped"},
      {"max_area_factor", "", d.max_area_factor, 1.1, 10, "larger blobs (x reference median area) are merged pins"},
      {"min_fill", "", d.min_fill, 0, 1, "blob area / bounding-box area (a disc: 0.785)"},
      {"max_aspect", "", d.max_aspect, 1, 10, "bounding-box aspect ratio of a pin"},
      {"gate_fraction", "", d.gate_fraction, 0.1, 0.5, "match gate as a fraction of the pin pitch"},
      {"outlier_fraction", "", d.outlier_fraction, 0.1, 1,
       "max disagreement with the neighbours, fraction of the pitch"},
      {"local_iterations", "", double(d.local_iterations), 1, 20, "rounds of the growth from the seeds"},
      {"rim_seeds", "", double(d.rim_seeds), 0, 1, "1: seeds on the rim at rest instead of the global fit"},
      {"rim_width", "pitch", d.rim_width, 0.5, 5, "outer band of pins used as rim seeds"},
      {"affine_prediction", "", double(d.affine_prediction), 0, 1, "1: local affine prediction, 0: neighbour median"},
  });
}

std::vector<PinDetection> detect_pins(const cv::Mat& image, const PinTrackerOptions& o, double reference_area_px) {
  const std::vector<Blob> blobs = blobs_of(image, o.threshold);
  double area = reference_area_px;
  if (area <= 0) {
    std::vector<double> a;
    for (const auto& b : blobs)
      if (b.fill >= o.min_fill && b.aspect <= o.max_aspect && b.area >= 4) a.push_back(b.area);
    area = median(a);
  }
  std::vector<PinDetection> out;
  for (const auto& b : blobs)
    if (b.area >= o.min_area_factor * area && b.area <= o.max_area_factor * area && b.fill >= o.min_fill &&
        b.aspect <= o.max_aspect)
      out.push_back({b.uv, b.area});
  return out;
}

PinReference make_pin_reference(const cv::Mat& reference, const PinTrackerOptions& o, const std::string& where) {
  // The reference is undeformed: pins are whole, so the area band is tighter than for a pressed image.
  PinTrackerOptions strict = o;
  strict.min_area_factor = std::max(o.min_area_factor, 0.5);
  const std::vector<PinDetection> det = detect_pins(reference, strict);
  if (det.size() < 10) throw InputError(where, "only " + std::to_string(det.size()) + " pins found in the reference");
  PinReference ref;
  std::vector<double> areas;
  for (const auto& d : det) {
    ref.rest_px.push_back(d.uv);
    areas.push_back(d.area_px);
  }
  std::sort(ref.rest_px.begin(), ref.rest_px.end(),
            [](const Vec2& a, const Vec2& b) { return a.y() != b.y() ? a.y() < b.y() : a.x() < b.x(); });
  ref.area_px = median(areas);
  std::vector<double> nn;
  for (std::size_t i = 0; i < ref.rest_px.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < ref.rest_px.size(); ++j)
      if (i != j) best = std::min(best, (ref.rest_px[i] - ref.rest_px[j]).norm());
    nn.push_back(best);
  }
  ref.pitch_px = median(nn);
  ref.neighbours = neighbours_within(ref.rest_px, kNeighbourRadius * ref.pitch_px);
  Vec2 centre = Vec2::Zero();
  for (const auto& p : ref.rest_px) centre += p;
  centre /= double(ref.rest_px.size());
  double outer = 0;
  for (const auto& p : ref.rest_px) outer = std::max(outer, (p - centre).norm());
  for (const auto& p : ref.rest_px) ref.on_rim.push_back((p - centre).norm() >= outer - o.rim_width * ref.pitch_px);
  return ref;
}

std::vector<Vec2> track_pins(const PinReference& ref, const std::vector<PinDetection>& detections,
                             const PinTrackerOptions& o, const std::vector<Vec2>& prior_disp) {
  const std::size_t n = ref.rest_px.size();
  if (!prior_disp.empty() && prior_disp.size() != n)
    throw std::invalid_argument("track_pins: prior has " + std::to_string(prior_disp.size()) + " pins, reference " +
                                std::to_string(n));
  std::vector<Vec2> prior = prior_disp.empty() ? std::vector<Vec2>(n, Vec2::Zero()) : prior_disp;
  for (auto& p : prior)
    if (!p.allFinite()) p = Vec2::Zero();
  std::vector<Vec2> det;
  det.reserve(detections.size());
  for (const auto& d : detections) det.push_back(d.uv);
  const double gate = o.gate_fraction * ref.pitch_px;
  const Vec2 lost(kNaN, kNaN);
  std::vector<Vec2> res(n, lost);  // residual disp - prior of the matched pins
  std::vector<char> taken(det.size(), 0);
  // Seeds: pins that match the global affine fit of the prior's prediction tightly and mutually (with the
  // rim option, outer pins matched at their rest position instead: the skin is held at its base).
  {
    std::vector<Vec2> start(n);
    for (std::size_t i = 0; i < n; ++i) start[i] = ref.rest_px[i] + prior[i];
    if (!o.rim_seeds) start = global_prediction(start, det, gate, ref.pitch_px);
    const std::vector<int> m = mutual_nearest(start, det, kSeedFraction * ref.pitch_px);
    for (std::size_t i = 0; i < n; ++i)
      if ((!o.rim_seeds || ref.on_rim[i]) && m[i] >= 0) {
        res[i] = det[m[i]] - ref.rest_px[i] - prior[i];
        taken[m[i]] = 1;
      }
  }
  // Growth: a pin next to matched pins is predicted from the residual of its matched surroundings and
  // takes the nearest free detection inside the gate; pins with the most matched neighbours go first, and
  // the rounds repeat while anything is added.
  for (int round = 0; round < o.local_iterations; ++round) {
    bool added = false;
    for (int need = 4; need >= 1; --need) {
      for (std::size_t i = 0; i < n; ++i) {
        if (res[i].allFinite()) continue;
        const auto pred = local_prediction(ref, prior, res, i, need, o.affine_prediction);
        if (!pred) continue;
        int best = -1;
        double d2 = gate * gate;
        for (std::size_t j = 0; j < det.size(); ++j) {
          const double e = (det[j] - *pred).squaredNorm();
          if (!taken[j] && e <= d2) {
            d2 = e;
            best = int(j);
          }
        }
        if (best < 0) continue;
        res[i] = det[best] - ref.rest_px[i] - prior[i];
        taken[best] = 1;
        added = true;
      }
    }
    if (!added) break;
  }
  // A match whose residual disagrees with the median of its matched rest-neighbours' took a neighbour's
  // pin: lost.
  std::vector<Vec2> kept(n, lost);
  for (std::size_t i = 0; i < n; ++i) {
    if (!res[i].allFinite()) continue;
    std::vector<Vec2> around;
    for (int j : ref.neighbours[i])
      if (res[j].allFinite()) around.push_back(res[j]);
    if (around.size() < 2 || (res[i] - median2(around)).norm() <= o.outlier_fraction * ref.pitch_px)
      kept[i] = res[i] + prior[i];
  }
  return kept;
}

std::vector<Vec2> track_pins(const PinReference& ref, const cv::Mat& image, const PinTrackerOptions& o,
                             const std::vector<Vec2>& prior_disp) {
  return track_pins(ref, detect_pins(image, o, ref.area_px), o, prior_disp);
}

}  // namespace sb
