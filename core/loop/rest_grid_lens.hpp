#pragma once
// The rest grid's lens: the markers are printed on a regular lattice, and a lens images that lattice bent
// about the principal point. The lattice's indices are assigned from the rest positions alone, then
//   rest_i = D_k1(o + A n_i)
// is fitted (Ceres): o the lattice origin (px), A its 2 x 2 pitch / rotation / shear (px per index), n_i the
// marker's integer index, and D_k1 the radial distortion of the lens_distortion effect (the same convention):
//   D(p) = c + (p - c)(1 + k1 r^2),  r = |p - c| / (image half-diagonal),  c = camera.principal_px.
// No contact model, right or wrong, touches the rest positions: k1 read here is evidence beyond model form
// (docs/effects.md, "Fingerprints"). What else bends a printed lattice between print and image (a domed gel
// seen from below, a print that is not regular) reads as k1 too.
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/sensor/camera.hpp"

namespace sb {

// D_k1 of the lens_distortion effect with k2 = 0, on an image point (px).
Vec2 lens_distort_px(const Camera& camera, double k1, const Vec2& p_px);

// The integer lattice index of each marker: indices are relative to the seed (the marker nearest the principal
// point), along the two shortest non-collinear neighbour offsets found there. Unassigned markers (NaN, or not
// reached by the growth) have assigned[i] = 0.
struct LatticeIndices {
  std::vector<Eigen::Vector2i> index;
  std::vector<std::uint8_t> assigned;
  Vec2 step_a_px = Vec2::Zero(), step_b_px = Vec2::Zero();  // the two offsets at the seed
  int count = 0;
};

// Assigns lattice indices, growing outwards from the seed: a neighbour of an assigned marker along +-a or
// +-b is predicted by extrapolating the spacing it already has on the other side (the local pitch a lens
// bends slowly), else by the seed's offset, and is the finite marker nearest that prediction if that marker
// is unassigned and within kLatticeAssignFraction of the step. Storage order plays no part; NaN markers are
// skipped. Fewer than 4 finite markers: nothing assigned.
LatticeIndices assign_lattice_indices(const std::vector<Vec2>& rest_px, const Vec2& principal_px);

// A neighbour is accepted within this fraction of the step of its prediction.
inline constexpr double kLatticeAssignFraction = 0.3;
// is_lattice: at least this many markers, spanning at least kMinLatticeSpan indices along each lattice axis ...
inline constexpr int kMinLatticeMarkers = 9;
inline constexpr int kMinLatticeSpan = 3;
// ... and an RMS fit residual below this fraction of the shorter pitch (a printed grid tracked at rest sits
// within a few hundredths of a pitch of its lattice; a pattern that is not one misses by a quarter pitch or more).
inline constexpr double kMaxLatticeRmsPitchFraction = 0.1;

struct RestGridLens {
  bool is_lattice = false;
  std::string why_not;  // when !is_lattice, the reason (for reports)
  double k1 = 0.0;
  double k1_stderr = 0.0;      // sqrt of (J^T J)^-1 at k1 times the residual variance SSE / (2 N - 7)
  double rms_px = 0.0;         // sqrt(sum |rest_i - D(o + A n_i)|^2 / N) over the markers used
  double pitch_px = 0.0;       // the shorter lattice step |A e_x|, |A e_y|
  double pitch_long_px = 0.0;  // the longer one
  double shift_rms_px = 0.0;   // RMS of |D(o + A n_i) - (o + A n_i)|: how far the fitted lens moves the grid
  Vec2 origin_px = Vec2::Zero();
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  int markers_used = 0;
  Eigen::Vector2i span = Eigen::Vector2i::Zero();  // distinct indices along each axis (max - min + 1)
  LatticeIndices indices;
};

// The rest grid's lattice and lens (see the file comment). NaN markers are skipped. Never throws on a pattern
// that is not a lattice: is_lattice is false with the reason.
RestGridLens rest_grid_lens(const Camera& camera, const std::vector<Vec2>& rest_px);

// The fitted lattice node n seen through the fitted lens: D(o + A n).
Vec2 rest_grid_node_px(const Camera& camera, const RestGridLens& fit, const Eigen::Vector2i& n);

// One line for reports: "a lattice of 63 markers (7 x 9, pitch 33.0 px) with k1 -0.150 +- 0.0003, RMS 0.05 px"
// or "not a lattice (<why>)".
std::string describe(const RestGridLens& fit);

}  // namespace sb
