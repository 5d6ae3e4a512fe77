#include "core/tracking/lattice_check.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>
#include <string>

namespace sb {
namespace {

double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

bool are_neighbours(const PinReference& ref, int i, int j) {
  const auto& nb = ref.neighbours[i];
  return std::find(nb.begin(), nb.end(), j) != nb.end();
}

// Index of the rest pin at `p` (Subdiv2D returns vertex coordinates as floats).
int pin_at(const PinReference& ref, const cv::Point2f& p) {
  int best = -1;
  double d2 = 1e-2;
  for (std::size_t i = 0; i < ref.rest_px.size(); ++i) {
    const double e = (ref.rest_px[i] - Vec2(p.x, p.y)).squaredNorm();
    if (e < d2) {
      d2 = e;
      best = int(i);
    }
  }
  return best;
}

// A detection other than the two ends inside the circle of radius margin x |a - b| / 2 about their middle.
bool site_between(const Vec2& a, const Vec2& b, const std::vector<PinDetection>& detections, double margin) {
  const Vec2 mid = 0.5 * (a + b);
  const double r2 = std::pow(0.5 * margin * (a - b).norm(), 2);
  constexpr double kSame2 = 1e-6;  // px^2: the ends themselves are detections
  for (const auto& d : detections) {
    if ((d.uv - a).squaredNorm() < kSame2 || (d.uv - b).squaredNorm() < kSame2) continue;
    if ((d.uv - mid).squaredNorm() < r2) return true;
  }
  return false;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Angle (radians, in [0, pi/3)) of the lattice's first row direction: the median of the lattice edges'
// angles modulo 60 degrees.
double lattice_angle(const PinReference& ref, const std::vector<std::pair<int, int>>& edges) {
  std::vector<double> a;
  for (const auto& [i, j] : edges) {
    const Vec2 e = ref.rest_px[j] - ref.rest_px[i];
    a.push_back(std::fmod(std::atan2(e.y(), e.x()) + 4 * M_PI, M_PI / 3));
  }
  return median_of(a);
}

// nb[k][i]: the rest neighbour of pin i in lattice direction k (0..5), -1 at the lattice's edge.
std::vector<std::vector<int>> directional_neighbours(const PinReference& ref,
                                                     const std::vector<std::pair<int, int>>& edges) {
  const double theta0 = lattice_angle(ref, edges);
  constexpr double kAngleTol = 30.0 * M_PI / 180.0;  // sectors: every first-ring edge falls in one
  std::vector<std::vector<int>> nb(6, std::vector<int>(ref.rest_px.size(), -1));
  for (const auto& [a, b] : edges)
    for (const auto& [i, j] : {std::pair{a, b}, std::pair{b, a}}) {
      const Vec2 e = ref.rest_px[j] - ref.rest_px[i];
      const double rel = std::remainder(std::atan2(e.y(), e.x()) - theta0, 2 * M_PI);
      const int k = (int(std::lround(rel / (M_PI / 3))) + 6) % 6;
      if (std::abs(std::remainder(rel - k * M_PI / 3, 2 * M_PI)) < kAngleTol) nb[k][i] = j;
    }
  return nb;
}

// Pins outside the largest group of unsuspected tracked pins joined by lattice edges are marked suspect:
// an island cut off by lost or suspect pins was registered on its own, and nothing ties its registration
// to the main field's (a slipped island inside a ring of lost pins has no boundary to show). Returns how
// many were marked.
int mark_detached(const PinReference& ref, const std::vector<Vec2>& disp, std::vector<char>& suspect) {
  const std::size_t n = ref.rest_px.size();
  std::vector<std::vector<int>> adj(n);
  for (const auto& [i, j] : lattice_edges(ref))
    if (disp[i].allFinite() && disp[j].allFinite() && !suspect[i] && !suspect[j]) {
      adj[i].push_back(j);
      adj[j].push_back(i);
    }
  std::vector<int> group(n, -1), size;
  for (std::size_t s = 0; s < n; ++s) {
    if (group[s] >= 0 || !disp[s].allFinite() || suspect[s]) continue;
    const int g = int(size.size());
    size.push_back(0);
    std::vector<int> todo{int(s)};
    group[s] = g;
    while (!todo.empty()) {
      const int i = todo.back();
      todo.pop_back();
      ++size[g];
      for (int j : adj[i])
        if (group[j] < 0) {
          group[j] = g;
          todo.push_back(j);
        }
    }
  }
  if (size.empty()) return 0;
  const int main_group = int(std::max_element(size.begin(), size.end()) - size.begin());
  int marked = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (group[i] >= 0 && group[i] != main_group) {
      suspect[i] = 1;
      ++marked;
    }
  return marked;
}

}  // namespace

std::vector<Vec2> without_suspects(const std::vector<Vec2>& disp, const LatticeCheckResult& check) {
  std::vector<Vec2> out = disp;
  for (std::size_t i = 0; i < out.size() && i < check.suspect.size(); ++i)
    if (check.suspect[i]) out[i] = Vec2(std::nan(""), std::nan(""));
  return out;
}

int registration_margin(const PinReference& ref, const std::vector<Vec2>& disp,
                        const std::vector<PinDetection>& detections) {
  const std::size_t n = ref.rest_px.size();
  int matched = 0;
  for (const auto& d : disp) matched += d.allFinite();
  // A detection is used when a tracked pin sits on it (within 0.1 pitch: detections are a pitch apart, and
  // a field given from elsewhere, e.g. a test's truth, may differ from the centroids by the rasterisation).
  const double used2 = std::pow(0.1 * ref.pitch_px, 2);
  int unmatched = 0;
  for (const auto& det : detections) {
    bool used = false;
    for (std::size_t i = 0; i < n && !used; ++i)
      used = disp[i].allFinite() && (ref.rest_px[i] + disp[i] - det.uv).squaredNorm() < used2;
    unmatched += !used;
  }
  const auto nb = directional_neighbours(ref, lattice_edges(ref));
  int best_alternative = 0;
  for (const auto& dir : nb) {
    int keep = 0;  // pins whose neighbour in this direction is matched: they could take its detection
    for (std::size_t i = 0; i < n; ++i) keep += dir[i] >= 0 && disp[dir[i]].allFinite();
    best_alternative = std::max(best_alternative, keep + unmatched);
  }
  return matched - best_alternative;
}

std::vector<std::pair<int, int>> lattice_edges(const PinReference& ref) {
  std::vector<PinDetection> rest;
  for (const auto& p : ref.rest_px) rest.push_back({p, ref.area_px});
  std::vector<std::pair<int, int>> edges;
  for (std::size_t i = 0; i < ref.rest_px.size(); ++i)
    for (int j : ref.neighbours[i])
      if (j > int(i) && !site_between(ref.rest_px[i], ref.rest_px[j], rest, 1.0)) edges.emplace_back(int(i), j);
  return edges;
}

std::vector<std::array<int, 3>> lattice_triangles(const PinReference& ref) {
  if (ref.rest_px.size() < 3) return {};
  double lo_u = 1e300, lo_v = 1e300, hi_u = -1e300, hi_v = -1e300;
  for (const auto& p : ref.rest_px) {
    lo_u = std::min(lo_u, p.x());
    lo_v = std::min(lo_v, p.y());
    hi_u = std::max(hi_u, p.x());
    hi_v = std::max(hi_v, p.y());
  }
  cv::Subdiv2D subdiv(cv::Rect(int(lo_u) - 2, int(lo_v) - 2, int(hi_u - lo_u) + 5, int(hi_v - lo_v) + 5));
  for (const auto& p : ref.rest_px) subdiv.insert(cv::Point2f(float(p.x()), float(p.y())));
  std::vector<cv::Vec6f> tris;
  subdiv.getTriangleList(tris);
  std::set<std::array<int, 3>> unique;
  for (const auto& t : tris) {
    std::array<int, 3> v{pin_at(ref, {t[0], t[1]}), pin_at(ref, {t[2], t[3]}), pin_at(ref, {t[4], t[5]})};
    if (v[0] < 0 || v[1] < 0 || v[2] < 0) continue;  // a corner of Subdiv2D's bounding triangle
    if (!are_neighbours(ref, v[0], v[1]) || !are_neighbours(ref, v[1], v[2]) || !are_neighbours(ref, v[2], v[0]))
      continue;
    if (signed_area(ref.rest_px[v[0]], ref.rest_px[v[1]], ref.rest_px[v[2]]) < 0) std::swap(v[1], v[2]);
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());  // one spelling per triangle
    unique.insert(v);
  }
  return {unique.begin(), unique.end()};
}

LatticeCheckResult check_lattice(const PinReference& ref, const std::vector<Vec2>& disp,
                                 const std::vector<PinDetection>& detections, const LatticeCheckOptions& o,
                                 const std::vector<Vec2>& prior) {
  const std::size_t n = ref.rest_px.size();
  if (disp.size() != n || (!prior.empty() && prior.size() != n))
    throw std::invalid_argument("check_lattice: field sizes " + std::to_string(disp.size()) + " / " +
                                std::to_string(prior.size()) + " differ from the reference's " + std::to_string(n));
  LatticeCheckResult r;
  r.suspect.assign(n, 0);
  for (const auto& [i, j] : lattice_edges(ref)) {
    if (!disp[i].allFinite() || !disp[j].allFinite()) continue;
    ++r.pairs_checked;
    const double step = (disp[i] - disp[j]).norm() / (ref.rest_px[i] - ref.rest_px[j]).norm();
    r.worst_relative_step = std::max(r.worst_relative_step, step);
    const bool slipped = step > o.max_relative_step;
    const bool skipped = site_between(ref.rest_px[i] + disp[i], ref.rest_px[j] + disp[j], detections, o.gabriel_margin);
    r.slipped_pairs += slipped;
    r.skipped_sites += skipped;
    if (slipped || skipped) r.suspect[i] = r.suspect[j] = 1;
  }
  for (const auto& t : lattice_triangles(ref)) {
    if (!disp[t[0]].allFinite() || !disp[t[1]].allFinite() || !disp[t[2]].allFinite()) continue;
    ++r.triangles_checked;
    const Vec2 a = ref.rest_px[t[0]] + disp[t[0]], b = ref.rest_px[t[1]] + disp[t[1]],
               c = ref.rest_px[t[2]] + disp[t[2]];
    if (signed_area(a, b, c) <= 0) {
      ++r.flipped_triangles;
      for (int v : t) r.suspect[v] = 1;
    }
  }
  r.detached_pins = mark_detached(ref, disp, r.suspect);
  // The whole-field tests judge what would be kept: a field whose slipped part is its larger part keeps
  // that part after the local tests, and only the pins left can show it.
  const std::vector<Vec2> kept = without_suspects(disp, r);
  std::vector<double> miss_u, miss_v, miss;
  for (std::size_t i = 0; i < n; ++i) {
    if (prior.empty() || !prior[i].allFinite()) continue;
    if (disp[i].allFinite()) {
      miss.push_back((disp[i] - prior[i]).norm());
      r.prior_misses += miss.back() > o.max_prior_miss * ref.pitch_px;
    }
    if (kept[i].allFinite()) {
      miss_u.push_back((kept[i] - prior[i]).x());
      miss_v.push_back((kept[i] - prior[i]).y());
    }
  }
  r.median_prior_miss_px = median_of(miss);
  r.coherent_prior_miss_px = Vec2(median_of(miss_u), median_of(miss_v)).norm();
  r.registration_margin = registration_margin(ref, kept, detections);
  r.field_shifted = r.registration_margin <= 0 || r.coherent_prior_miss_px > o.max_coherent_prior_miss * ref.pitch_px;
  if (r.field_shifted)
    for (std::size_t i = 0; i < n; ++i) r.suspect[i] = disp[i].allFinite();
  return r;
}

}  // namespace sb
