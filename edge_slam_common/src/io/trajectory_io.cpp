#include "edge_slam/io/trajectory_io.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace edge_slam {

void write_pose_fields(std::ostream& out, const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d t = T.translation();
  out << std::fixed << std::setprecision(7) << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y()
      << ' ' << q.z() << ' ' << q.w() << '\n';
}

void write_tum_pose(std::ostream& out, double stamp, const Eigen::Isometry3d& T_wc) {
  out << std::fixed << std::setprecision(6) << stamp << ' ';
  write_pose_fields(out, T_wc);
}

void write_tum_trajectory(const std::string& path,
                          const std::vector<std::pair<double, Eigen::Isometry3d>>& poses_wc) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write trajectory file '" + path + "'");
  out << "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& [stamp, T] : poses_wc) write_tum_pose(out, stamp, T);
  if (!out) throw std::runtime_error("error while writing '" + path + "'");
}

std::vector<std::pair<double, Eigen::Isometry3d>> read_tum_trajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open trajectory file '" + path + "'");
  std::vector<std::pair<double, Eigen::Isometry3d>> out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double s, tx, ty, tz, qx, qy, qz, qw;
    if (!(ss >> s >> tx >> ty >> tz >> qx >> qy >> qz >> qw))
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected 8 numbers");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(tx, ty, tz);
    out.emplace_back(s, T);
  }
  return out;
}

}  // namespace edge_slam
