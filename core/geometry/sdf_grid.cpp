// A dense regular-grid cache of any Sdf.
//
// Nodes: n_d = round(extent_d / voxel) + 1 nodes per axis at region.min() + i * voxel (i = 0 .. n_d - 1), the
// node layout of pytorch_volumetric's VoxelGrid (get_divisible_range_by_resolution +
// get_coordinates_and_points_in_grid). The covered box is [min, min + (n - 1) * voxel]; when the region's
// extent is not a multiple of the voxel its max side moves to the nearest multiple.
//
// Lookups:
//  - Trilinear: interpolation of the eight surrounding nodes; exact for fields linear in x, y, z (a half
//    space, a plane); the gradient is the analytic gradient of the interpolant, normalised.
//  - Nearest: pytorch_volumetric.CachedSDF, the lookup HydroShear's code uses: index = round((p - min) / voxel) per
//  axis, the
//    value and the source gradient stored at that node; piecewise constant.
// Out of range (a Trilinear query outside the covered box; a Nearest query whose rounded index falls outside
// [0, n - 1], i.e. more than half a voxel beyond the box): the source field is evaluated directly. That is what
// CachedSDF.__call__ does (it hands out-of-bound points to its ground-truth gt_sdf), and it keeps the cache
// a pure accelerator: never wrong far away, only slower there.
//
// Storage: float values (4 bytes a node, plus 12 for the Nearest gradients), filled in parallel with TBB
// through the source's batch queries, one x-row per batch.
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/geometry/sdf.hpp"

namespace sb {
namespace {

class GridSdf final : public Sdf {
 public:
  GridSdf(SdfPtr source, const Eigen::AlignedBox3d& region, double voxel, GridLookup lookup)
      : source_(std::move(source)), origin_(region.min()), voxel_(voxel), inv_voxel_(1.0 / voxel), lookup_(lookup) {
    for (int d = 0; d < 3; ++d) {
      const double cells = std::round(region.sizes()[d] / voxel);
      if (!(cells >= 1) || cells > 1e5) throw std::invalid_argument("make_grid_sdf: region/voxel gives no usable grid");
      n_[d] = static_cast<int>(cells) + 1;
    }
    fill();
  }

  double value(const Vec3& p) const override {
    return lookup_ == GridLookup::kNearest ? nearest(p, nullptr) : trilinear(p, nullptr);
  }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    return lookup_ == GridLookup::kNearest ? nearest(p, g) : trilinear(p, g);
  }
  Eigen::AlignedBox3d bounds() const override { return {origin_, node(n_[0] - 1, n_[1] - 1, n_[2] - 1)}; }
  std::string describe() const override {
    std::ostringstream s;
    s << "grid cache " << n_[0] << " x " << n_[1] << " x " << n_[2] << " nodes at " << voxel_ * 1e3 << " mm, "
      << (lookup_ == GridLookup::kNearest ? "nearest-node" : "trilinear") << " lookup of [" << source_->describe()
      << "]";
    return s.str();
  }

 private:
  Vec3 node(int i, int j, int k) const { return origin_ + voxel_ * Vec3(i, j, k); }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * n_[1] + static_cast<std::size_t>(j)) * n_[0] + static_cast<std::size_t>(i);
  }

  void fill() {
    const std::size_t total = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
    phi_.resize(total);
    if (lookup_ == GridLookup::kNearest) gradient_.resize(total);
    tbb::parallel_for(tbb::blocked_range2d<int>(0, n_[2], 0, n_[1]), [&](const tbb::blocked_range2d<int>& r) {
      std::vector<Vec3> row(static_cast<std::size_t>(n_[0]));
      std::vector<double> phi(row.size());
      std::vector<Vec3> grad(row.size());
      for (int k = r.rows().begin(); k < r.rows().end(); ++k)
        for (int j = r.cols().begin(); j < r.cols().end(); ++j) {
          for (int i = 0; i < n_[0]; ++i) row[static_cast<std::size_t>(i)] = node(i, j, k);
          if (lookup_ == GridLookup::kNearest)
            source_->values_and_gradients(row, phi, grad);
          else
            source_->values(row, phi);
          const std::size_t base = index(0, j, k);
          for (std::size_t i = 0; i < row.size(); ++i) {
            phi_[base + i] = static_cast<float>(phi[i]);
            if (lookup_ == GridLookup::kNearest) gradient_[base + i] = grad[i].cast<float>();
          }
        }
    });
  }

  double nearest(const Vec3& p, Vec3* g) const {
    const Vec3 x = (p - origin_) * inv_voxel_;
    int id[3];
    for (int d = 0; d < 3; ++d) {
      const double r = std::round(x[d]);
      if (r < 0 || r > n_[d] - 1) return fallback(p, g);
      id[d] = static_cast<int>(r);
    }
    const std::size_t at = index(id[0], id[1], id[2]);
    if (g) *g = gradient_[at].cast<double>();
    return phi_[at];
  }

  double trilinear(const Vec3& p, Vec3* g) const {
    const Vec3 x = (p - origin_) * inv_voxel_;
    int c[3];
    double t[3];
    for (int d = 0; d < 3; ++d) {
      if (!(x[d] >= 0 && x[d] <= n_[d] - 1)) return fallback(p, g);
      c[d] = std::min(static_cast<int>(x[d]), n_[d] - 2);  // the last node belongs to the last cell
      t[d] = x[d] - c[d];
    }
    double v[2][2][2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int e = 0; e < 2; ++e) v[a][b][e] = phi_[index(c[0] + a, c[1] + b, c[2] + e)];
    auto lerp = [](double lo, double hi, double s) { return lo + (hi - lo) * s; };
    // Bilinear in (y, z) on the two x faces, then linear in x; the partials follow the same pattern.
    const double f0 = lerp(lerp(v[0][0][0], v[0][0][1], t[2]), lerp(v[0][1][0], v[0][1][1], t[2]), t[1]);
    const double f1 = lerp(lerp(v[1][0][0], v[1][0][1], t[2]), lerp(v[1][1][0], v[1][1][1], t[2]), t[1]);
    if (g) {
      const double gx = f1 - f0;
      const double gy = lerp(lerp(v[0][1][0] - v[0][0][0], v[0][1][1] - v[0][0][1], t[2]),
                             lerp(v[1][1][0] - v[1][0][0], v[1][1][1] - v[1][0][1], t[2]), t[0]);
      const double gz = lerp(lerp(v[0][0][1] - v[0][0][0], v[0][1][1] - v[0][1][0], t[1]),
                             lerp(v[1][0][1] - v[1][0][0], v[1][1][1] - v[1][1][0], t[1]), t[0]);
      const Vec3 grad(gx, gy, gz);
      const double n = grad.norm();
      if (n > 0)
        *g = grad / n;
      else
        source_->value_and_gradient(p, g);  // a flat cell: ask the source for a direction
    }
    return lerp(f0, f1, t[0]);
  }

  double fallback(const Vec3& p, Vec3* g) const { return g ? source_->value_and_gradient(p, g) : source_->value(p); }

  SdfPtr source_;
  Vec3 origin_;
  double voxel_, inv_voxel_;
  GridLookup lookup_;
  int n_[3] = {0, 0, 0};
  std::vector<float> phi_;
  std::vector<Eigen::Vector3f> gradient_;
};

}  // namespace

SdfPtr make_grid_sdf(SdfPtr source, const Eigen::AlignedBox3d& region, double voxel_size, GridLookup lookup) {
  if (!source) throw std::invalid_argument("make_grid_sdf: no source field");
  if (!(voxel_size > 0) || region.isEmpty()) throw std::invalid_argument("make_grid_sdf: empty region or voxel <= 0");
  return std::make_shared<GridSdf>(std::move(source), region, voxel_size, lookup);
}

}  // namespace sb
