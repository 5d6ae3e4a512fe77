// A TacTip set's targets.csv rows and the pose path each describes (tactip_targets.hpp).
#include "core/data/tactip_targets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/base/error.hpp"

namespace sb {

namespace {

// One CSV cell as written by spreadsheets and pandas: surrounding blanks and a pair of double quotes dropped.
std::string csv_cell(std::string c) {
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\r'; };
  while (!c.empty() && blank(c.back())) c.pop_back();
  std::size_t b = 0;
  while (b < c.size() && blank(c[b])) ++b;
  c.erase(0, b);
  if (c.size() >= 2 && c.front() == '"' && c.back() == '"') c = c.substr(1, c.size() - 2);
  return c;
}

std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(csv_cell(c));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

// targets.csv as users have it: LF or CRLF line ends, a UTF-8 byte-order mark, the columns in any order with
// others beside them (found by name), the rows in any order.
std::vector<TactipTarget> read_tactip_targets(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  std::string line;
  std::getline(in, line);
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
  const std::vector<std::string> header = csv_cells(line);
  auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw InputError(path, 1, 1, "column '" + name + "' missing");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t ci = col("sensor_image"), cz = col("pose_z"), crx = col("pose_Rx"), cry = col("pose_Ry"),
                    csx = col("shear_x"), csy = col("shear_y"), crz = col("shear_Rz");
  std::vector<TactipTarget> out;
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (csv_cell(line).empty()) continue;
    const std::vector<std::string> cells = csv_cells(line);
    if (cells.size() != header.size())
      throw InputError(path, lineno, 1,
                       "expected " + std::to_string(header.size()) + " columns, got " + std::to_string(cells.size()));
    auto num = [&](std::size_t c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (end == cells[c].c_str() || *end != '\0' || !std::isfinite(v))
        throw InputError(path, lineno, int(c) + 1, "'" + cells[c] + "' is not a finite number");
      return v;
    };
    TactipTarget t;
    t.image = cells[ci];
    if (std::sscanf(t.image.c_str(), "image_%d.png", &t.number) != 1 || t.number <= 0)
      throw InputError(path, lineno, int(ci) + 1, "sensor_image '" + t.image + "' is not image_N.png with N > 0");
    t.depth_mm = num(cz);
    t.rx_deg = num(crx);
    t.ry_deg = num(cry);
    t.sx_mm = num(csx);
    t.sy_mm = num(csy);
    t.twist_deg = num(crz);
    out.push_back(t);
  }
  if (out.empty()) throw InputError(path, "no samples");
  return out;
}

// Motion label: the larger of shear (|s| / 5 mm) and twist (|w| / 5 deg), both normalised by the collection's
// usual range; a sample with both under a quarter of it is a press (+ tilt): "dilation". A label for the
// per-motion scores, not a measurement.
std::string tactip_motion(const TactipTarget& t) {
  const double s = std::hypot(t.sx_mm, t.sy_mm) / 5.0, w = std::abs(t.twist_deg) / 5.0;
  if (std::max(s, w) < 0.25) return "dilation";
  return s >= w ? "shear" : "twist";
}

// Covariates of a sample's pin field for the prior (pin_field_prior.hpp), inputs scaled to about [-1, 1]
// (the scale only conditions the regression; its predictions do not depend on it): the press d and d^2 (the
// contact grows with the press), the tilt (a, b) to third order (it moves the contact across the dome) alone
// and times d, the slide (sx, sy) and twist w alone and times d and the tilt (the stick region's size, hence
// how much of the slide the skin follows, grows with the press).
Eigen::VectorXd tactip_covariates(const TactipTarget& t) {
  const double d = t.depth_mm / 5.0, a = t.rx_deg / 25.0, b = t.ry_deg / 25.0, sx = t.sx_mm / 5.0, sy = t.sy_mm / 5.0,
               w = t.twist_deg / 5.0;
  std::vector<double> f{1.0, d, d * d};
  for (double x : {a, b, a * a, a * b, b * b, a * a * a, a * a * b, a * b * b, b * b * b}) {
    f.push_back(x);
    f.push_back(d * x);
  }
  for (double x : {sx, sy, w}) {
    f.push_back(x);
    f.push_back(d * x);
    f.push_back(a * x);
    f.push_back(b * x);
  }
  return Eigen::Map<const Eigen::VectorXd>(f.data(), Eigen::Index(f.size()));
}

// Frames (SOURCE.md, env_params.json): the work frame W has z down into the surface (the surface plane is
// z_W = 0, its body z_W > 0), the tool frame S sits at the TacTip's tip with z along the sensor's axis
// (out of the skin). tactip_pose_path returns X_SI with X_SI = X_WS^-1 (S at the undeformed skin apex, +z out
// of the skin); the importer turns S about z into E so that E's x/y are the image's u/v. And
// the indenter frame I = W (contact face z_I = 0, body z_I > 0). The robot sets X_WS: translation
// (shear_x, shear_y, -above) above, (shear_x, shear_y, depth) pressed, (0, 0, depth) final, rotation
// Rz(twist) Ry(ry) Rx(rx) (static x-y-z Euler angles) with the twist going to zero during the slide.
// The path is X_SI = X_WS^-1.
std::vector<Pose> tactip_pose_path(double depth_m, double rx, double ry, double sx_m, double sy_m, double twist,
                                   int slide_steps, double above_m) {
  auto X_WS = [&](double f, double z) {  // f = 1 at the start of the slide, 0 at its end
    Pose X = Pose::Identity();
    X.linear() = (Eigen::AngleAxisd(f * twist, Vec3::UnitZ()) * Eigen::AngleAxisd(ry, Vec3::UnitY()) *
                  Eigen::AngleAxisd(rx, Vec3::UnitX()))
                     .toRotationMatrix();
    X.translation() = Vec3(f * sx_m, f * sy_m, z);
    return X;
  };
  std::vector<Pose> path{X_WS(1.0, -above_m).inverse()};
  const int n = std::max(1, slide_steps);
  for (int k = 0; k <= n; ++k) path.push_back(X_WS(1.0 - double(k) / n, depth_m).inverse());
  return path;
}

}  // namespace sb
