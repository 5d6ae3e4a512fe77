// What a TacTip's tracked presses identify of its sensor: the image-from-tool rotation and the contact onset
// (tactip_identify.hpp).
#include "core/sensor/tactip_identify.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "core/base/error.hpp"
#include "core/base/median.hpp"

namespace sb {

Vec2 most_displaced_mean(const std::vector<Vec2>& disp_px, int* tracked) {
  std::vector<const Vec2*> d;
  for (const Vec2& v : disp_px)
    if (v.allFinite()) d.push_back(&v);
  if (tracked) *tracked = int(d.size());
  if (d.empty()) return Vec2(kNaN, kNaN);
  const std::size_t top = std::max<std::size_t>(1, d.size() / 10);
  std::partial_sort(d.begin(), d.begin() + std::ptrdiff_t(top), d.end(),
                    [](const Vec2* a, const Vec2* b) { return a->squaredNorm() > b->squaredNorm(); });
  Vec2 m = Vec2::Zero();
  for (std::size_t k = 0; k < top; ++k) m += *d[k];
  return m / double(top);
}

namespace {

using Complex = std::complex<double>;
Complex as_complex(const Vec2& v) { return {v.x(), v.y()}; }

// Least squares m = c s over the samples: c and the residual RMS per component (2 n - 2 degrees of freedom).
struct ComplexFit {
  Complex c;
  double rms = kNaN, sigma_c = kNaN;
};
ComplexFit fit_complex(const std::vector<Complex>& s, const std::vector<Complex>& m) {
  Complex num = 0;
  double den = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    num += m[k] * std::conj(s[k]);
    den += std::norm(s[k]);
  }
  ComplexFit f;
  f.c = num / den;
  double sse = 0;
  for (std::size_t k = 0; k < s.size(); ++k) sse += std::norm(m[k] - f.c * s[k]);
  f.rms = std::sqrt(sse / double(s.size()));
  const double var = sse / double(2 * s.size() - 2);  // per component
  f.sigma_c = std::sqrt(var / den);
  return f;
}

}  // namespace

ImageFromTool identify_image_from_tool(const std::vector<ShearResponse>& samples, const std::string& where,
                                       double min_depth_mm) {
  constexpr double kMinSlideFraction = 0.3;
  constexpr int kMinSamples = 8;
  std::vector<double> depths;
  double max_slide = 0;
  auto usable = [&](const ShearResponse& s) {
    return s.tracked && s.response_px.allFinite() && s.depth_mm > min_depth_mm;
  };
  for (const auto& s : samples)
    if (usable(s)) {
      depths.push_back(s.depth_mm);
      max_slide = std::max(max_slide, s.shear_mm.norm());
    }
  const double shallow = percentile_nearest_rank(depths, 0.5);  // the upper median
  std::vector<Complex> sh, sh_mirrored, m;
  for (const auto& s : samples)
    if (usable(s) && s.depth_mm <= shallow && s.shear_mm.norm() >= kMinSlideFraction * max_slide && max_slide > 0) {
      sh.push_back(as_complex(s.shear_mm));
      sh_mirrored.push_back(std::conj(as_complex(s.shear_mm)));
      m.push_back(as_complex(s.response_px));
    }
  if (int(sh.size()) < kMinSamples)
    throw InputError(where, std::to_string(sh.size()) +
                                " shallow presses with a slide: the image-from-tool rotation needs at least " +
                                std::to_string(kMinSamples) + " (give image_from_tool_deg with --sensor)");
  const ComplexFit rotated = fit_complex(sh, m), mirrored = fit_complex(sh_mirrored, m);
  ImageFromTool out;
  out.samples = int(sh.size());
  double total = 0;
  for (const Complex& v : m) total += std::norm(v);
  out.response_rms_px = std::sqrt(total / double(m.size()));
  out.rms_px = rotated.rms;
  out.mirrored_rms_px = mirrored.rms;
  out.mirrored = mirrored.rms < rotated.rms;
  const ComplexFit& f = out.mirrored ? mirrored : rotated;
  out.angle_rad = std::arg(f.c);
  out.gain_px_per_mm = std::abs(f.c);
  out.sigma_rad = f.sigma_c / std::abs(f.c);
  return out;
}

double fraction_moved(const std::vector<Vec2>& disp_px, double threshold_px) {
  int tracked = 0, moved = 0;
  for (const Vec2& v : disp_px)
    if (v.allFinite()) {
      ++tracked;
      moved += v.norm() > threshold_px;
    }
  return tracked ? double(moved) / tracked : 0.0;
}

ContactOnset identify_contact_onset(const std::vector<ShearResponse>& samples) {
  constexpr double kMinSlideFraction = 0.5;
  double max_slide = 0;
  for (const auto& s : samples)
    if (s.tracked) max_slide = std::max(max_slide, s.shear_mm.norm());
  std::vector<const ShearResponse*> use;
  for (const auto& s : samples)
    if (s.tracked && s.shear_mm.norm() >= kMinSlideFraction * max_slide && max_slide > 0) use.push_back(&s);
  std::sort(use.begin(), use.end(), [](auto* a, auto* b) { return a->depth_mm < b->depth_mm; });
  std::vector<const ShearResponse*> in;
  for (auto* s : use)
    if (s->moving_fraction > 0) in.push_back(s);
  ContactOnset out;
  in.resize(in.size() / 3);
  if (in.size() < 4) return out;
  // y = k (d - d0) = k d + b: ordinary least squares, d0 = -b / k, its sigma by the delta method.
  const double n = double(in.size());
  double sd = 0, sy = 0;
  for (auto* s : in) {
    sd += s->depth_mm;
    sy += s->moving_fraction;
  }
  const double md = sd / n, my = sy / n;
  double sxx = 0, sxy = 0;
  for (auto* s : in) {
    sxx += (s->depth_mm - md) * (s->depth_mm - md);
    sxy += (s->depth_mm - md) * (s->moving_fraction - my);
  }
  if (!(sxx > 0) || !(sxy > 0)) return out;
  const double k = sxy / sxx, b = my - k * md;
  double sse = 0;
  for (auto* s : in) sse += std::pow(s->moving_fraction - (k * s->depth_mm + b), 2);
  const double var = sse / (n - 2);
  const double var_k = var / sxx, var_b = var * (1.0 / n + md * md / sxx), cov_kb = -md * var / sxx;
  const double d0 = -b / k;
  // d0 = -b / k: gradient (-1 / k, b / k^2).
  const double gb = -1.0 / k, gk = b / (k * k);
  out.extrapolated_mm = d0;
  out.sigma_mm = std::sqrt(std::max(0.0, gb * gb * var_b + gk * gk * var_k + 2 * gb * gk * cov_kb));
  out.in_contact = int(in.size());
  out.shallowest_in_mm = in.front()->depth_mm;
  for (auto* s : use)
    if (s->moving_fraction == 0 && s->depth_mm < d0 + out.sigma_mm) {
      ++out.out_of_contact;
      out.deepest_out_mm = std::isnan(out.deepest_out_mm) ? s->depth_mm : std::max(out.deepest_out_mm, s->depth_mm);
    }
  out.identified = out.out_of_contact > 0;
  return out;
}

}  // namespace sb
