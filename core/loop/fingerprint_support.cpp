// What every fingerprint shares (fingerprint_support.hpp).
#include "core/loop/fingerprint_support.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/base/format.hpp"

namespace sb {

bool frame_moved(const std::vector<Vec2>& meas_px) {
  for (const Vec2& d : meas_px)
    if (d.allFinite() && d.norm() >= kMotionThresholdPx) return true;
  return false;
}

double marker_pitch_px(const Sensor& sensor) {
  const auto& m = sensor.markers_rest_px;
  double pitch = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = i + 1; j < m.size(); ++j) pitch = std::min(pitch, (m[i] - m[j]).norm());
  if (!std::isfinite(pitch) || pitch <= 0) throw std::invalid_argument("fingerprint: need two distinct markers");
  return pitch;
}

std::vector<std::vector<int>> interior_neighbours(const Sensor& sensor) {
  const auto& m = sensor.markers_rest_px;
  const double reach = 1.2 * marker_pitch_px(sensor);
  std::vector<std::vector<int>> nb(m.size());
  std::size_t most = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    for (std::size_t j = 0; j < m.size(); ++j)
      if (i != j && (m[i] - m[j]).norm() < reach) nb[i].push_back(static_cast<int>(j));
    most = std::max(most, nb[i].size());
  }
  for (auto& list : nb)
    if (list.size() < most) list.clear();
  return nb;
}

double laplacian_energy(const std::vector<std::vector<int>>& nb, const std::vector<Vec2>& f) {
  double e = 0;
  for (std::size_t i = 0; i < nb.size(); ++i) {
    if (nb[i].empty() || !f[i].allFinite()) continue;
    Vec2 mean = Vec2::Zero();
    bool finite = true;
    for (int j : nb[i]) {
      mean += f[static_cast<std::size_t>(j)];
      finite = finite && f[static_cast<std::size_t>(j)].allFinite();
    }
    if (finite) e += (mean / static_cast<double>(nb[i].size()) - f[i]).squaredNorm();
  }
  return e;
}

void require_fingerprint_flags(const FingerprintSample& s, const char* who) {
  if (s.in_contact.size() != s.meas_px.size() || s.held.size() != s.meas_px.size())
    throw std::invalid_argument(std::string(who) + ": need one contact and one held flag per frame (" +
                                std::to_string(s.meas_px.size()) + " frames, " + std::to_string(s.in_contact.size()) +
                                " and " + std::to_string(s.held.size()) + " flags)");
}

bool splits_agree(double a, double b, double agreement) {
  if (!(std::isfinite(a) && std::isfinite(b)) || a == 0 || b == 0 || (a > 0) != (b > 0)) return false;
  return std::max(a / b, b / a) <= agreement;
}

std::string estimate_text(double v) { return format_number(v, "%.3g", "nan"); }

FingerprintCheck::Band agreement_band(const std::string& name, double estimate, double agreement) {
  const double a = estimate / agreement, b = estimate * agreement;
  return {name, estimate, std::min(a, b), std::max(a, b)};
}

void conclude_finding(FingerprintCheck* c, const std::string& missing_cal, const std::string& missing_val,
                      bool agreeing, const FingerprintRules& rules) {
  if (!missing_cal.empty())
    c->verdict = "calibration: " + missing_cal;
  else if (!missing_val.empty())
    c->verdict = "validation: " + missing_val;
  else if (!agreeing)
    c->verdict = "the splits disagree (" + estimate_text(c->calibration) + " vs " + estimate_text(c->validation) +
                 ", more than x" + estimate_text(rules.agreement) + ")";
  else
    c->verdict = "found on both splits";
  c->consistent = missing_cal.empty() && missing_val.empty() && agreeing;
}

}  // namespace sb
