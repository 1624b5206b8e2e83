// The two text files a split run's final trajectory is composed from (tools/compose_trajectory,
// data/trajectory_anchors.h). Poses are "tx ty tz qx qy qz qw"; '#' lines are comments.
//
// The mobile's anchors file (written while it tracks):
//   F <frame stamp> <reference KeyFrame id> <T_ref_c>      a tracked frame on its reference KeyFrame
//   K <KeyFrame id> <parent KeyFrame id> <T_parent_kf>     a new KeyFrame on its parent, as tracked
// The edge's KeyFrames file (rewritten atomically while it maps):
//   <KeyFrame id> <stamp> <T_wc>                           a Global-Map KeyFrame's current pose
//   C <KeyFrame id> <parent KeyFrame id> <T_parent_kf>     a KeyFrame Local-Mapping culled, on the
//                                                          parent it had then (the map's final word)
#pragma once
#include <Eigen/Geometry>
#include <ostream>
#include <string>
#include <vector>

#include "edge_slam/data/trajectory_anchors.h"

namespace edge_slam {

const char* anchors_file_header();
void write_anchor(std::ostream& out, const FrameAnchor& frame);        // one F line
void write_anchor(std::ostream& out, const KeyFrameLink& keyframe);    // one K line
std::string edge_keyframes_text(const EdgeKeyFrames& keyframes);       // the whole file

// Throw std::runtime_error naming file:line on a malformed line.
MobileAnchors read_mobile_anchors(const std::string& path);
EdgeKeyFrames read_edge_keyframes(const std::string& path);

}  // namespace edge_slam
