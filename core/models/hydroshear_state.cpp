// HydroShear's phases 1 and 2 (core/models/hydroshear_step.hpp): the candidate points and the tracker step.
#include <algorithm>
#include <span>
#include <vector>

#include "core/models/hydroshear_kernels.hpp"
#include "core/models/hydroshear_step.hpp"

namespace sb::hydroshear {

namespace kernels = hydroshear_kernels;

namespace {
// Metres added to the cull bound so rounding of the cluster test can never drop a point whose own
// transform would give z_E < cull_z.
constexpr double kCullMargin = 1e-9;

kernels::AdvanceColumns advance_view(const StepColumns& c) {
  return {c.s_prev.data(), c.qx.data(), c.qy.data(), c.qz.data(), c.s.data(),  c.px.data(), c.py.data(),
          c.pz.data(),     c.ox.data(), c.oy.data(), c.oz.data(), c.nx.data(), c.ny.data(), c.nz.data()};
}
// The rotation of X row-major and its translation, as the kernels take them.
struct PoseArrays {
  double r[9], t[3];
  explicit PoseArrays(const Pose& X) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r[3 * i + j] = X.linear()(i, j);
      t[i] = X.translation()[i];
    }
  }
};

// phi[i] = m.phi_E(p_i + shift) for columns of points; `points` is scratch for a general gel's one batch call (an
// analytic gel vectorises it: the TacTip's dome).
void phi_columns(const HydroShearModel& m, const double* x, const double* y, const double* z, const Vec3& shift, int n,
                 double* phi, std::vector<Vec3>& points) {
  if (m.flat) return kernels::flat_pad_phi(m.pad, shift.data(), x, y, z, n, phi);
  points.resize(n);
  for (int i = 0; i < n; ++i) points[i] = Vec3(x[i], y[i], z[i]) + shift;
  m.sensor->gel_sdf->values(points, std::span<double>(phi, n));
}

// Normal of the n/t split for the points at `pos`, pointing out of the gel: +z_E (code) or minus the
// indenter's outward normal (paper).
void normals(const HydroShearModel& m, const Mat3& R_EI, const std::vector<int>& pos, StepColumns& in) {
  if (!m.k.normal_indenter) return;  // +z: the kernels do not read the columns
  const int n = static_cast<int>(pos.size());
  const std::vector<Vec3>& n_I = m.table->n_I;
  for (int j = 0; j < n; ++j) {
    const Vec3 nh = -(R_EI * n_I[pos[j]]);
    in.nx[j] = nh.x();
    in.ny[j] = nh.y();
    in.nz[j] = nh.z();
  }
}

// in.o*[j] = the state u of the point at pos[j] in `from` (sorted by position), or 0 when `from` does
// not hold it (the point was outside the gel). A merge of two sorted lists, then the copies.
void lookup_state(const PointColumns& from, const std::vector<int>& pos, std::vector<int>& index, StepColumns& in) {
  const int n = static_cast<int>(pos.size()), m = from.size();
  index.resize(n);
  const int* fp = from.pos.data();
  const int* p = pos.data();
  int* ix = index.data();
  for (int j = 0, k = 0; j < n; ++j) {
    while (k < m && fp[k] < p[j]) ++k;
    ix[j] = k < m && fp[k] == p[j] ? k : -1;
  }
  const double *ux = from.ux.data(), *uy = from.uy.data(), *uz = from.uz.data();
  double *ox = in.ox.data(), *oy = in.oy.data(), *oz = in.oz.data();
  for (int j = 0; j < n; ++j) {
    const int i = ix[j];
    ox[j] = i >= 0 ? ux[i] : 0.0;
    oy[j] = i >= 0 ? uy[i] : 0.0;
    oz[j] = i >= 0 ? uz[i] : 0.0;
  }
}

}  // namespace

void PointColumns::resize(int n) {
  pos.resize(n);
  for (auto* v : {&ux, &uy, &uz}) v->resize(n);
  slip.resize(n);
}

void PointColumns::swap(PointColumns& o) noexcept {
  pos.swap(o.pos);
  ux.swap(o.ux);
  uy.swap(o.uy);
  uz.swap(o.uz);
  slip.swap(o.slip);
}

void StepColumns::resize(int n) {
  for (auto* v : {&s_prev, &qx, &qy, &qz, &s, &px, &py, &pz, &ox, &oy, &oz, &nx, &ny, &nz, &un}) v->resize(n);
}

// The points that may be in the gel now (or at the augmented pose), with o_i in E and m.phi_E(o_i).
const Candidates& gather_candidates(const HydroShearModel& m, const Pose& X_EI, Candidates& sc) {
  const PointTable& table = *m.table;
  const Mat3 R = X_EI.linear();
  const Vec3 t = X_EI.translation();
  const bool aug = m.k.g_aug > 0;
  const Vec3 shift = m.k.g_aug * m.k.g_dir_E;
  // z_E of a cluster centre is R.row(2) c + t_z; its points are within radius of it. With the
  // augmentation the shifted points must be tested too, so the lower of the two heights counts.
  const Vec3 r_z = R.row(2).transpose();
  const double z_shift_down = aug ? std::min(shift.z(), 0.0) : 0.0;
  // A sphere (centre c, radius r in I) is entirely above the cull plane, also after the shift.
  auto above = [&](const Cluster& c) {
    if (m.box_cull) {
      const Vec3 c_E = R * c.centre_I + t;
      return ((c_E.array() + c.radius) < m.gel_box.min().array()).any() ||
             ((c_E.array() - c.radius) > m.gel_box.max().array()).any();
    }
    return m.cull && r_z.dot(c.centre_I) + t.z() + z_shift_down - c.radius > m.cull_z + kCullMargin;
  };
  sc.ranges.clear();
  int visited = 0;
  auto keep = [&](const Cluster& c) {
    if (!sc.ranges.empty() && sc.ranges.back().second == c.begin)
      sc.ranges.back().second = c.end;
    else
      sc.ranges.emplace_back(c.begin, c.end);
    visited += c.end - c.begin;
  };
  for (const Cluster& g : table.groups) {
    if (above(g)) continue;
    for (int ci = g.begin; ci < g.end; ++ci)
      if (!above(table.clusters[ci])) keep(table.clusters[ci]);
  }
  for (auto* v : {&sc.vx, &sc.vy, &sc.vz, &sc.vs}) v->resize(visited);
  const PoseArrays X(X_EI);
  int off = 0;
  for (const auto& [b, e] : sc.ranges) {
    kernels::transform_points(X.r, X.t, &table.pIx[b], &table.pIy[b], &table.pIz[b], e - b, &sc.vx[off], &sc.vy[off],
                              &sc.vz[off]);
    off += e - b;
  }
  phi_columns(m, sc.vx.data(), sc.vy.data(), sc.vz.data(), Vec3::Zero(), visited, sc.vs.data(), sc.points);
  if (aug) {
    sc.vs_aug.resize(visited);
    phi_columns(m, sc.vx.data(), sc.vy.data(), sc.vz.data(), shift, visited, sc.vs_aug.data(), sc.points);
  }
  // Branch-free compaction of the indices alone (whether a point is in the gel is not predictable):
  // every point is written at entry n and n advances only for a kept one, so one spare entry.
  sc.cpos.resize(visited + 1);
  sc.ci.resize(visited + 1);
  int n = 0, i = 0;
  for (const auto& [b, e] : sc.ranges)
    for (int pos = b; pos < e; ++pos, ++i) {
      sc.cpos[n] = pos;
      sc.ci[n] = i;
      n += static_cast<int>(sc.vs[i] < 0) | static_cast<int>(aug && sc.vs_aug[i] < 0);
    }
  sc.cpos.resize(n);
  sc.ci.resize(n);
  return sc;
}

// The tracker step: candidates inside the gel advance from their old state (or from zero when they
// enter); every other point's state is reset to zero, i.e. dropped from the sparse list.
FieldPoints commit_state(const HydroShearModel& m, const Candidates& cand, const Pose& X_EI, Slot& slot,
                         StateBuffers& buf) {
  // The authors' first call after a reset sets prev = current, so penetration already present then
  // is lost (docs/models.md, HydroShear).
  if (slot.first) slot.X_prev = X_EI;
  const int nc = static_cast<int>(cand.cpos.size());
  const int* ci = cand.ci.data();
  const double* vs = cand.vs.data();
  int n_in = 0;
  for (int c = 0; c < nc; ++c) n_in += vs[ci[c]] < 0;
  StepColumns& in = buf.commit;
  PointColumns& next = buf.next;
  in.resize(n_in + 1);  // + 1: the branch-free compaction writes one entry past the last kept
  next.resize(n_in + 1);
  {
    const double *vx = cand.vx.data(), *vy = cand.vy.data(), *vz = cand.vz.data();
    double *px = in.px.data(), *py = in.py.data(), *pz = in.pz.data(), *s = in.s.data();
    int* pos = next.pos.data();
    for (int c = 0, j = 0; c < nc; ++c) {
      const int i = ci[c];
      pos[j] = cand.cpos[c];
      px[j] = vx[i];
      py[j] = vy[i];
      pz[j] = vz[i];
      s[j] = vs[i];
      j += vs[i] < 0;
    }
  }
  in.resize(n_in);
  next.resize(n_in);
  lookup_state(slot.points, next.pos, buf.old_index, in);
  // Each point's previous position o_{t-1} = X_prev X^-1 o_t (one transform of the columns at hand).
  // On the first step o_{t-1} = o_t exactly (the authors' prev = current), not through a rounded identity.
  if (slot.first) {
    in.qx = in.px;
    in.qy = in.py;
    in.qz = in.pz;
  } else {
    const PoseArrays X_PE(slot.X_prev * X_EI.inverse(Eigen::Isometry));
    kernels::transform_points(X_PE.r, X_PE.t, in.px.data(), in.py.data(), in.pz.data(), n_in, in.qx.data(),
                              in.qy.data(), in.qz.data());
  }
  // phi_E at the previous pose only matters for a point that enters the gel: for one that was in the
  // gel (s_prev < 0) and still is, alpha = (-s + s_prev) / (s_prev - s) = 1 exactly, whatever s_prev,
  // and s_prev = s gives that 1 through the 0/0 rule.
  const int* ix = buf.old_index.data();
  for (int j = 0; j < n_in; ++j) in.s_prev[j] = ix[j] >= 0 ? in.s[j] : m.phi_E(Vec3(in.qx[j], in.qy[j], in.qz[j]));
  normals(m, X_EI.linear(), next.pos, in);
  kernels::advance_points(advance_view(in), !m.k.normal_indenter, m.k.mu * m.k.E / m.k.K, n_in, next.ux.data(),
                          next.uy.data(), next.uz.data(), in.un.data(), next.slip.data());
  slot.points.swap(next);
  slot.X_prev = X_EI;
  slot.first = false;
  return {&slot.points, in.un.data(), in.s.data(),  in.px.data(), in.py.data(),
          in.pz.data(), in.nx.data(), in.ny.data(), in.nz.data()};
}

// The state the field uses with the augmentation: one virtual, uncommitted step from the committed
// state toward the points shifted by g_aug dir.
FieldPoints augmented_state(const HydroShearModel& m, const Candidates& cand, const Pose& X_EI, const Slot& slot,
                            StateBuffers& buf) {
  const Vec3 shift = m.k.g_aug * m.k.g_dir_E;
  const int nc = static_cast<int>(cand.cpos.size());
  int n_aug = 0;
  for (int c = 0; c < nc; ++c) n_aug += cand.vs_aug[cand.ci[c]] < 0;
  StepColumns& in = buf.augment;
  PointColumns& out = buf.aug;
  in.resize(n_aug);
  out.resize(n_aug);
  for (int c = 0, j = 0; c < nc; ++c) {
    const int i = cand.ci[c];
    if (cand.vs_aug[i] >= 0) continue;
    in.qx[j] = cand.vx[i];
    in.qy[j] = cand.vy[i];
    in.qz[j] = cand.vz[i];
    in.s_prev[j] = cand.vs[i];
    in.px[j] = cand.vx[i] + shift.x();
    in.py[j] = cand.vy[i] + shift.y();
    in.pz[j] = cand.vz[i] + shift.z();
    in.s[j] = cand.vs_aug[i];
    out.pos[j] = cand.cpos[c];
    ++j;
  }
  lookup_state(slot.points, out.pos, buf.old_index, in);
  normals(m, X_EI.linear(), out.pos, in);
  kernels::advance_points(advance_view(in), !m.k.normal_indenter, m.k.mu * m.k.E / m.k.K, n_aug, out.ux.data(),
                          out.uy.data(), out.uz.data(), in.un.data(), out.slip.data());
  // phi_E at the shifted point; the real, unshifted points (q).
  return {&out,         in.un.data(), in.s.data(),  in.qx.data(), in.qy.data(),
          in.qz.data(), in.nx.data(), in.ny.data(), in.nz.data()};
}

}  // namespace sb::hydroshear
