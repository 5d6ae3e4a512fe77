#include "app/frame_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "widgets/panels.hpp"

namespace sb::app {

std::string percentiles_line(std::vector<double> ms) {
  if (ms.empty()) return "no frames";
  std::sort(ms.begin(), ms.end());
  const auto pct = [&](double p) {
    return ms[std::min(ms.size() - 1, static_cast<std::size_t>(std::floor(p * (ms.size() - 1) + 0.5)))];
  };
  char buf[200];
  std::snprintf(buf, sizeof buf, "%zu frames: p50 %.1f ms (%.1f fps)  p90 %.1f ms  p99 %.1f ms  max %.1f ms", ms.size(),
                pct(0.5), 1000.0 / pct(0.5), pct(0.9), pct(0.99), ms.back());
  return buf;
}

std::string text_report(const AppSnapshot& snap) {
  std::ostringstream r;
  r << "step " << snap.step << " of " << snap.num_steps - 1 << " (t = " << std::max(0, snap.step) * snap.dt_s
    << " s)\n";
  for (const auto& m : snap.models) {
    double max_px = 0, sum = 0;
    int contact = 0;
    for (const Vec2& d : m.out.disp_px) {
      max_px = std::max(max_px, d.norm());
      sum += d.norm();
    }
    for (auto c : m.out.marker_in_contact) contact += c != 0;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "  %-18s step %7.2f ms (mean of %ld)  |d| max %.3f px  mean %.3f px  markers in contact %d\n",
                  ui::display_name(m.id).c_str(), m.timing.mean_ms, m.timing.count, max_px,
                  m.out.disp_px.empty() ? 0.0 : sum / m.out.disp_px.size(), contact);
    r << buf;
  }
  return r.str();
}

}  // namespace sb::app
