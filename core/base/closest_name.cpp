#include "core/base/closest_name.hpp"

#include <algorithm>
#include <cctype>
#include <limits>

namespace sb {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

int edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  // d[i][j]: the distance between a's first i and b's first j characters (one row per i, kept whole for the swap).
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const int substitution = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

std::string closest_name(const std::string& typed, const std::vector<std::string>& known) {
  const std::string t = lower(typed);
  const int allowed = std::max<int>(1, static_cast<int>(t.size()) / 3);
  std::string best;
  int best_distance = std::numeric_limits<int>::max();
  for (const std::string& name : known) {
    const int distance = edit_distance(t, lower(name));
    if (distance < best_distance) {
      best_distance = distance;
      best = name;
    }
  }
  return best_distance <= allowed ? best : "";
}

std::string did_you_mean(const std::string& typed, const std::vector<std::string>& known) {
  const std::string name = closest_name(typed, known);
  return name.empty() ? "" : " (did you mean '" + name + "'?)";
}

}  // namespace sb
