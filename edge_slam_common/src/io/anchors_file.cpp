#include "edge_slam/io/anchors_file.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "edge_slam/io/trajectory_io.h"

namespace edge_slam {
namespace {

// "tx ty tz qx qy qz qw" from a stream; false when a number is missing or the rotation is null.
bool read_pose(std::istream& in, Eigen::Isometry3d& T) {
  double tx, ty, tz, qx, qy, qz, qw;
  if (!(in >> tx >> ty >> tz >> qx >> qy >> qz >> qw)) return false;
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  if (!(q.norm() > 1e-6)) return false;
  T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(tx, ty, tz);
  return true;
}

bool at_end(std::istream& in) {
  std::string rest;
  return !(in >> rest);
}

// Calls parse(line stream, first word) for each data line; it returns false on a bad line.
template <class Parse>
void read_lines(const std::string& path, Parse parse) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot open '" + path + "'");
  std::string line;
  for (int number = 1; std::getline(file, line); ++number) {
    std::istringstream in(line);
    std::string first;
    if (!(in >> first) || first[0] == '#') continue;
    if (!parse(in, first) || !at_end(in))
      throw std::runtime_error(path + ":" + std::to_string(number) + ": malformed line: " + line);
  }
}

bool read_link(std::istream& in, KeyFrameLink& link) {
  return static_cast<bool>(in >> link.id >> link.parent_id) && read_pose(in, link.T_parent_kf);
}

}  // namespace

const char* anchors_file_header() {
  return "# F <frame stamp> <reference KF id> <T_ref_c: tx ty tz qx qy qz qw>\n"
         "# K <KF id> <parent KF id> <T_parent_kf: tx ty tz qx qy qz qw>   (tools/compose_trajectory)\n";
}

void write_anchor(std::ostream& out, const FrameAnchor& frame) {
  out << "F " << std::fixed << std::setprecision(6) << frame.stamp << ' ' << frame.reference_id << ' ';
  write_pose_fields(out, frame.T_ref_c);
}

void write_anchor(std::ostream& out, const KeyFrameLink& keyframe) {
  out << "K " << keyframe.id << ' ' << keyframe.parent_id << ' ';
  write_pose_fields(out, keyframe.T_parent_kf);
}

std::string edge_keyframes_text(const EdgeKeyFrames& keyframes) {
  std::ostringstream out;
  out << "# keyframe_id timestamp tx ty tz qx qy qz qw (T_wc, Global-Map)\n"
      << "# C keyframe_id parent_id tx ty tz qx qy qz qw (T_parent_kf of a culled KeyFrame)\n";
  for (const KeyFramePose& kf : keyframes.in_map) {
    out << kf.id << ' ';
    write_tum_pose(out, kf.stamp, kf.T_wc);
  }
  for (const KeyFrameLink& link : keyframes.culled) {
    out << "C " << link.id << ' ' << link.parent_id << ' ';
    write_pose_fields(out, link.T_parent_kf);
  }
  return out.str();
}

MobileAnchors read_mobile_anchors(const std::string& path) {
  MobileAnchors a;
  read_lines(path, [&a](std::istream& in, const std::string& tag) {
    if (tag == "F") {
      FrameAnchor f;
      if (!(in >> f.stamp >> f.reference_id) || !read_pose(in, f.T_ref_c)) return false;
      a.frames.push_back(f);
      return true;
    }
    if (tag == "K") {
      KeyFrameLink k;
      if (!read_link(in, k)) return false;
      a.keyframes.push_back(k);
      return true;
    }
    return false;
  });
  return a;
}

EdgeKeyFrames read_edge_keyframes(const std::string& path) {
  EdgeKeyFrames e;
  read_lines(path, [&e](std::istream& in, const std::string& first) {
    if (first == "C") {
      KeyFrameLink link;
      if (!read_link(in, link)) return false;
      e.culled.push_back(link);
      return true;
    }
    KeyFramePose kf;
    size_t used = 0;
    try {
      const unsigned long id = std::stoul(first, &used);
      if (used != first.size() || id >= kNoId) return false;
      kf.id = static_cast<uint32_t>(id);
    } catch (const std::exception&) {
      return false;
    }
    if (!(in >> kf.stamp) || !read_pose(in, kf.T_wc)) return false;
    e.in_map.push_back(kf);
    return true;
  });
  return e;
}

}  // namespace edge_slam
