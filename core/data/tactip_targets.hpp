#pragma once
// A TacTip set's targets.csv rows (the pose of each sample), the regression covariates and the pose path each row
// describes.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb {

struct TactipTarget {
  std::string image;
  int number = 0;
  double depth_mm = 0, rx_deg = 0, ry_deg = 0, sx_mm = 0, sy_mm = 0, twist_deg = 0;
};

// targets.csv as users have it: LF or CRLF line ends, a UTF-8 byte-order mark, the columns in any order with
// others beside them (found by name), the rows in any order. InputError naming the file, line and column.
std::vector<TactipTarget> read_tactip_targets(const std::string& path);

// Motion label: "shear", "twist" or "dilation" (a press + tilt) by the larger normalised magnitude.
std::string tactip_motion(const TactipTarget& target);

// Covariates of a sample's pin field for the prior (pin_field_prior.hpp), inputs scaled to about [-1, 1].
Eigen::VectorXd tactip_covariates(const TactipTarget& target);

// The flat surface's pose path X_SI in the tool frame S (the importer turns it into E) for one TacTip sample (SI
// units): depth d, tilt (rx, ry) and twist w in radians, shear (sx, sy) in metres. See tactip_targets.cpp for the frame
// conventions. above_m: the clearance of the first ("above") frame.
std::vector<Pose> tactip_pose_path(double depth_m, double rx, double ry, double sx_m, double sy_m, double twist,
                                   int slide_steps, double above_m);

}  // namespace sb
