// A TacTip's sensor description and what the data identify of it (tactip_sensor.hpp).
#include "core/data/tactip_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/data/json_read.hpp"

namespace sb {

std::string to_string(SensorValueSource source) {
  switch (source) {
    case SensorValueSource::kIdentified: return "identified";
    case SensorValueSource::kGiven: return "given";
    case SensorValueSource::kDefault: break;
  }
  return "default";
}

namespace {
// The keys and values of a (const or not) TactipSensor, in the file's order.
template <typename Sensor, typename Value>
std::vector<std::pair<std::string, Value*>> value_list(Sensor& s) {
  return {{"dome_radius_mm", &s.dome_radius_mm},
          {"pin_depth_mm", &s.pin_depth_mm},
          {"ring_pitch_deg", &s.ring_pitch_deg},
          {"focal_px", &s.focal_px},
          {"distance_mm", &s.distance_mm},
          {"k1", &s.k1},
          {"principal_u_px", &s.principal_u_px},
          {"principal_v_px", &s.principal_v_px},
          {"image_from_tool_deg", &s.image_from_tool_deg},
          {"mirrored", &s.mirrored},
          {"contact_onset_mm", &s.contact_onset_mm}};
}
}  // namespace

std::vector<std::pair<std::string, SensorValue*>> TactipSensor::values() {
  return value_list<TactipSensor, SensorValue>(*this);
}

std::vector<std::pair<std::string, const SensorValue*>> TactipSensor::values() const {
  return value_list<const TactipSensor, const SensorValue>(*this);
}

TactipSensor tactip_standard_defaults() {
  TactipSensor s;
  s.dome_radius_mm = {20.0, kNaN, SensorValueSource::kDefault,
                      "the standard TacTip's 40 mm hemispherical tip (Lepora group, J. Robot. Biomim. 2017, fig. 2); "
                      "the rings cannot tell it from the camera distance"};
  s.pin_depth_mm = {3.0, kNaN, SensorValueSource::kDefault,
                    "assumed: 1 mm skin + about 2 mm pins; only moves the fitted distance"};
  s.ring_pitch_deg = {8.0, kNaN, SensorValueSource::kDefault,
                      "the printed pin pattern: 10 rings of 6 i pins, 8 deg apart in polar angle (to 80 deg); the "
                      "rings fix only its product with the focal length"};
  s.focal_px = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.distance_mm = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.k1 = {0.0, kNaN, SensorValueSource::kDefault, "no distortion: it trades with the distance at third order"};
  s.principal_u_px = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.principal_v_px = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the reference's pin rings"};
  s.image_from_tool_deg = {kNaN, kNaN, SensorValueSource::kDefault, "fitted to the shallow presses' slide"};
  s.mirrored = {0.0, kNaN, SensorValueSource::kDefault, "the camera sees the tool axes rotated, not mirrored"};
  s.contact_onset_mm = {0.0, kNaN, SensorValueSource::kDefault, "the collection's zero depth is the touch"};
  return s;
}

void apply_tactip_sensor_json(const nlohmann::json& j, const std::string& file, TactipSensor* into) {
  jsonin::require_object(j, file, "");
  const nlohmann::json* values = jsonin::find(j, "values");
  const std::string base = values ? "/values" : "";
  const nlohmann::json& obj = values ? *values : j;
  jsonin::require_object(obj, file, base);
  auto keys = into->values();
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string ptr = jsonin::child(base, it.key());
    if (!values && (it.key() == "type" || it.key() == "crop_px" || it.key() == "reference" ||
                    it.key().rfind("onset_extrapolated", 0) == 0))
      continue;
    const auto k = std::find_if(keys.begin(), keys.end(), [&](const auto& p) { return p.first == it.key(); });
    if (k == keys.end()) {
      std::string known;
      for (const auto& p : keys) known += (known.empty() ? "" : ", ") + p.first;
      jsonin::fail(file, ptr, "unknown sensor value (known: " + known + ")");
    }
    const nlohmann::json* v = &it.value();
    std::string vptr = ptr;
    if (v->is_object()) {
      v = &jsonin::member(*v, "value", file, ptr);
      vptr = jsonin::child(ptr, "value");
    }
    if (v->is_null()) continue;  // not known: identified or defaulted as without the file
    SensorValue& out = *k->second;
    out.value = v->is_boolean() ? double(v->get<bool>()) : jsonin::finite_number(*v, file, vptr);
    out.sigma = kNaN;
    out.source = SensorValueSource::kGiven;
    out.how = "given in " + file;
  }
  if (into->dome_radius_mm.value <= 0) jsonin::fail(file, jsonin::child(base, "dome_radius_mm"), "must be > 0");
  if (!(into->pin_depth_mm.value >= 0 && into->pin_depth_mm.value < into->dome_radius_mm.value))
    jsonin::fail(file, jsonin::child(base, "pin_depth_mm"), "must be >= 0 and below dome_radius_mm");
  for (const char* key : {"ring_pitch_deg", "focal_px", "distance_mm"}) {
    const auto k = std::find_if(keys.begin(), keys.end(), [&](const auto& p) { return p.first == key; });
    if (k->second->source == SensorValueSource::kGiven && !(k->second->value > 0))
      jsonin::fail(file, jsonin::child(base, key), "must be > 0");
  }
}

void read_tactip_sensor_file(const std::string& path, TactipSensor* into) {
  apply_tactip_sensor_json(jsonin::load_file(path), path, into);
}

nlohmann::ordered_json to_json(const TactipSensor& s) {
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  for (const auto& [key, v] : s.values()) {
    nlohmann::ordered_json e;
    e["value"] = std::isfinite(v->value) ? nlohmann::ordered_json(v->value) : nlohmann::ordered_json();
    e["sigma"] = std::isfinite(v->sigma) ? nlohmann::ordered_json(v->sigma) : nlohmann::ordered_json();
    e["source"] = to_string(v->source);
    e["how"] = v->how;
    values[key] = e;
  }
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  return {{"type", s.type},
          {"crop_px", {s.width_px, s.height_px}},
          {"reference", s.reference},
          {"values", values},
          {"onset_extrapolated_mm", number(s.onset_extrapolated_mm)},
          {"onset_extrapolated_sigma_mm", number(s.onset_extrapolated_sigma_mm)}};
}

std::vector<std::string> tactip_sensor_lines(const nlohmann::json& d) {
  std::vector<std::string> out;
  if (!d.is_object() || !d.contains("values")) return out;
  if (d.contains("reference")) out.push_back("reference: " + d.at("reference").get<std::string>());
  for (auto it = d.at("values").begin(); it != d.at("values").end(); ++it) {
    const auto& e = it.value();
    std::string line = it.key() + " ";
    line += e.value("value", nlohmann::json()).is_number() ? format_number(e.at("value").get<double>(), "%.4g") : "-";
    if (e.value("sigma", nlohmann::json()).is_number())
      line += " +- " + format_number(e.at("sigma").get<double>(), "%.2g");
    line += " (" + e.value("source", std::string("?")) + ": " + e.value("how", std::string()) + ")";
    out.push_back(line);
  }
  return out;
}

// ---- identification ---------------------------------------------------------------------------------------

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

double median_of(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

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
  const double shallow = median_of(depths);
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
