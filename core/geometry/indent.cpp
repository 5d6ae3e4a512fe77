#include "core/geometry/indent.hpp"

#include <cmath>
#include <vector>

namespace sb {

int indent_down(const Sdf& phi_I, const Pose& X_EI, std::span<Vec3> p_E, const IndentOptions& options) {
  const Pose X_IE = X_EI.inverse();
  const Vec3 down_I = X_IE.linear() * Vec3(0, 0, -1);
  // The points still inside, in I, and the field there: one batch query per step (OpenVDB accessors).
  std::vector<std::size_t> active;
  std::vector<Vec3> q_I;
  std::vector<double> phi;
  q_I.reserve(p_E.size());
  for (std::size_t i = 0; i < p_E.size(); ++i) q_I.push_back(X_IE * p_E[i]);
  phi.resize(q_I.size());
  phi_I.values(q_I, phi);
  std::vector<double> travelled;
  for (std::size_t i = 0; i < q_I.size(); ++i)
    if (phi[i] < 0) active.push_back(i);
  const int moved = static_cast<int>(active.size());
  travelled.assign(p_E.size(), 0.0);
  std::vector<Vec3> batch;
  std::vector<double> batch_phi;
  for (int step = 0; step < options.max_steps && !active.empty(); ++step) {
    batch.clear();
    for (std::size_t k = 0; k < active.size(); ++k) {
      const std::size_t i = active[k];
      const double s = -phi[i];
      travelled[i] += s;
      q_I[i] += s * down_I;
      batch.push_back(q_I[i]);
    }
    batch_phi.resize(batch.size());
    phi_I.values(batch, batch_phi);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < active.size(); ++k) {
      phi[active[k]] = batch_phi[k];
      if (batch_phi[k] < -options.tolerance_m) active[kept++] = active[k];
    }
    active.resize(kept);
  }
  for (std::size_t i = 0; i < p_E.size(); ++i) p_E[i].z() -= travelled[i];
  return moved;
}

}  // namespace sb
