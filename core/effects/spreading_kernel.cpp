#include "core/effects/spreading_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

namespace sb::effects {

SpreadingKernel spreading_kernel(const std::vector<Vec3>& p_EM, double sigma) {
  const std::size_t n = p_EM.size();
  SpreadingKernel kernel(n * n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    double* row = &kernel[j * n];
    double sum = 0.0;
    for (std::size_t k = 0; k < n; ++k)
      sum += row[k] = std::exp(-(p_EM[j] - p_EM[k]).squaredNorm() / (2 * sigma * sigma));
    for (std::size_t k = 0; k < n; ++k) row[k] /= sum;
  }
  return kernel;
}

std::shared_ptr<const SpreadingKernel> shared_spreading_kernel(const std::vector<Vec3>& p_EM, double sigma) {
  struct Entry {
    std::vector<Vec3> pins;
    double sigma;
    std::weak_ptr<const SpreadingKernel> kernel;
  };
  static std::mutex mutex;
  static std::vector<Entry> entries;
  const std::lock_guard<std::mutex> lock(mutex);
  std::erase_if(entries, [](const Entry& e) { return e.kernel.expired(); });
  for (const Entry& e : entries)
    if (e.sigma == sigma && e.pins == p_EM)
      if (auto k = e.kernel.lock()) return k;
  auto k = std::make_shared<const SpreadingKernel>(spreading_kernel(p_EM, sigma));
  entries.push_back({p_EM, sigma, k});
  return k;
}

}  // namespace sb::effects
