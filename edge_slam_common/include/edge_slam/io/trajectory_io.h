// TUM trajectory format: "timestamp tx ty tz qx qy qz qw" (camera-to-world pose T_wc).
#pragma once
#include <Eigen/Geometry>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace edge_slam {

void write_tum_pose(std::ostream& out, double stamp, const Eigen::Isometry3d& T_wc);
// "tx ty tz qx qy qz qw\n" of a pose (the TUM line without its stamp).
void write_pose_fields(std::ostream& out, const Eigen::Isometry3d& T);
// Writes all poses; throws std::runtime_error if the file cannot be written.
void write_tum_trajectory(const std::string& path,
                          const std::vector<std::pair<double, Eigen::Isometry3d>>& poses_wc);
// Reads a TUM trajectory (lines starting with '#' skipped); throws with file:line on bad input.
std::vector<std::pair<double, Eigen::Isometry3d>> read_tum_trajectory(const std::string& path);

}  // namespace edge_slam
