#pragma once
// The release phase of a recording whose indenter pose is unknown: after the contact ends every model's
// field is zero (HydroShear's state resets when its points leave the gel, TacSL's penalty and FOTS's
// dilation need penetration, FOTS's shear needs contact), so whatever the markers still show is residual,
// all of it effect. This finds that phase from the marker field alone and tests one explanation, the
// delayed recovery of a standard linear solid (viscoelastic_creep): the field left at release fading as
//   d_i(t) = d_i(t0) [c + (1 - c) exp(-(t - t0) / tau)],
// c the part that does not recover within the recording (adhesion, a slower mode). tau and c are fitted
// on the first half of the release frames and scored on the second half (held out in time), against
// the models' zero prediction.
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb {

struct ReleaseFit {
  double tau_s = 0;           // recovery time constant (the largest grid value means: no visible decay)
  bool tau_at_bound = false;  // tau hit the top of the search grid: only a lower bound
  double permanent = 0;       // c: the fraction of the release field that stays
};

struct ReleasePhase {
  bool found = false;
  std::string why_not;  // when not found: still in contact at the end, too few frames, ...
  int peak_frame = -1;
  double peak_mean_px = 0;  // largest per-frame mean |d| (the loaded field)
  int release_frame = -1;   // t0: first frame of the release phase
  int frames = 0;           // frames from t0 to the end
  double left_mean_px = 0;  // mean |d| at t0: what is left after unloading
  double left_max_px = 0;
  double end_mean_px = 0;              // mean |d| at the last frame
  ReleaseFit fit;                      // on the first half of the release frames
  double heldout_rmse_zero_px = 0;     // second half: the models (zero field)
  double heldout_rmse_fit_px = 0;      // second half: the recovery law
  double heldout_rmse_persist_px = 0;  // second half: d = d(t0) (nothing recovers), the law's c = 1 limit
};

// Mean |d| per frame over the markers the tracker kept (NaN markers skipped; NaN for an empty frame).
std::vector<double> mean_displacement_per_frame(const std::vector<std::vector<Vec2>>& disp_px);

// The release phase: the frames after the last frame at >= kLoadedFraction of the peak mean |d|, from
// the first one below kReleasedFraction of the peak once the field stops dropping fast (a frame keeping
// >= 80 % of the previous one's mean |d|), provided no later frame climbs back above 30 % of the peak.
// Needs >= kMinReleaseFrames frames (4: two to fit, two to score).
ReleasePhase analyse_release(const std::vector<std::vector<Vec2>>& disp_px, double dt_s);

// Fits tau and c of the recovery law to frames [first, last) of disp_px, the field at t0 = disp_px[t0]
// (least squares over every marker component; tau on a log grid from dt to 1000 s, c in [0, 1] in closed
// form for each tau).
ReleaseFit fit_release(const std::vector<std::vector<Vec2>>& disp_px, int t0, int first, int last, double dt_s);
// RMSE (px) of the recovery law over frames [first, last) (fit = nullptr: of the zero field).
double release_rmse(const std::vector<std::vector<Vec2>>& disp_px, int t0, int first, int last, double dt_s,
                    const ReleaseFit* fit);

}  // namespace sb
