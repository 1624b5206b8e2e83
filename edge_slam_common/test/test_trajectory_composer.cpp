// The one trajectory composer (data/trajectory_anchors.h) and the split's anchor files
// (io/anchors_file.h): frames follow their KeyFrame's final pose, through the map's parent
// relation for a culled KeyFrame and the mobile's for one the edge refused; a frame whose chain
// never reaches the map is counted and left out, never placed somewhere invented.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "edge_slam/data/trajectory_anchors.h"
#include "edge_slam/io/anchors_file.h"
#include "support/yaw_pose.h"

namespace edge_slam {
namespace {

using test_support::yaw_pose;
Eigen::Isometry3d pose(double x, double y, double z, double yaw) { return yaw_pose(x, y, z, yaw); }

FrameAnchor frame(double stamp, uint32_t reference, const Eigen::Isometry3d& T_ref_c) {
  return FrameAnchor{stamp, reference, T_ref_c};
}
KeyFrameLink link(uint32_t id, uint32_t parent, const Eigen::Isometry3d& T_parent_kf) {
  return KeyFrameLink{id, parent, T_parent_kf};
}

TEST(TrajectoryComposer, FrameFollowsItsKeyFramesFinalPose) {
  TrajectoryComposer c;
  const Eigen::Isometry3d T_w1 = pose(1, 0, 2, 0.3), T_1c = pose(0.1, 0, 0, 0.05);
  c.set_keyframe_pose(1, T_w1);
  const ComposedTrajectory t = c.compose({frame(5.0, 1, T_1c)});
  ASSERT_EQ(t.poses.size(), 1u);
  EXPECT_EQ(t.poses[0].first, 5.0);
  EXPECT_TRUE(t.poses[0].second.isApprox(T_w1 * T_1c, 1e-12));
  EXPECT_EQ(t.unanchored, 0u);
}

TEST(TrajectoryComposer, CulledKeyFramesFramesFollowItsParentsFinalPose) {
  const Eigen::Isometry3d T_12 = pose(0.2, 0, 0.1, 0.1), T_2c = pose(0.05, 0.01, 0, -0.02);
  for (const Eigen::Isometry3d& T_w1 : {pose(0, 0, 0, 0), pose(3, -1, 2, 1.2)}) {  // the parent corrected by a loop
    TrajectoryComposer c;
    c.set_parent_link(link(2, 1, T_12));  // KeyFrame 2 was culled: only its relation to 1 is left
    c.set_keyframe_pose(1, T_w1);
    const ComposedTrajectory t = c.compose({frame(1.0, 2, T_2c)});
    ASSERT_EQ(t.poses.size(), 1u);
    EXPECT_TRUE(t.poses[0].second.isApprox(T_w1 * T_12 * T_2c, 1e-12));
  }
}

TEST(TrajectoryComposer, AChainOfCulledKeyFramesIsWalkedToTheMap) {
  TrajectoryComposer c;
  const Eigen::Isometry3d T_w1 = pose(1, 2, 3, 0.4), T_12 = pose(0.1, 0, 0, 0.1), T_23 = pose(0, 0.1, 0, 0.2);
  c.set_parent_link(link(3, 2, T_23));
  c.set_parent_link(link(2, 1, T_12));
  c.set_keyframe_pose(1, T_w1);
  ASSERT_TRUE(c.keyframe_pose(3).has_value());
  EXPECT_TRUE(c.keyframe_pose(3)->isApprox(T_w1 * T_12 * T_23, 1e-12));
  EXPECT_TRUE(c.keyframe_pose(2)->isApprox(T_w1 * T_12, 1e-12));
}

TEST(TrajectoryComposer, AFinalPoseWinsOverALink) {
  TrajectoryComposer c;
  c.set_keyframe_pose(1, pose(0, 0, 0, 0));
  c.set_parent_link(link(2, 1, pose(5, 5, 5, 0)));
  c.set_keyframe_pose(2, pose(1, 0, 0, 0));
  EXPECT_TRUE(c.keyframe_pose(2)->isApprox(pose(1, 0, 0, 0), 1e-12));
}

TEST(TrajectoryComposer, AFrameWhoseChainNeverReachesTheMapIsCountedNotInvented) {
  TrajectoryComposer c;
  c.set_keyframe_pose(1, pose(0, 0, 0, 0));
  c.set_parent_link(link(9, 8, pose(0.1, 0, 0, 0)));  // 8: neither in the map nor linked
  c.set_parent_link(link(6, 7, pose(0.1, 0, 0, 0)));  // 6 -> 7 -> 6: a cycle, no map pose
  c.set_parent_link(link(7, 6, pose(0.1, 0, 0, 0)));
  const ComposedTrajectory t = c.compose({frame(1, 1, pose(0, 0, 0, 0)), frame(2, 9, pose(0, 0, 0, 0)),
                                          frame(3, 42, pose(0, 0, 0, 0)), frame(4, 6, pose(0, 0, 0, 0)),
                                          frame(5, 1, pose(0, 0, 1, 0))});
  EXPECT_EQ(t.unanchored, 3u);
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.poses[0].first, 1.0);
  EXPECT_EQ(t.poses[1].first, 5.0);
  EXPECT_FALSE(c.keyframe_pose(9).has_value());
}

TEST(SplitComposer, AKeyFrameTheEdgeRefusedIsReachedThroughTheMobilesParentChain) {
  MobileAnchors mobile;
  mobile.keyframes.push_back(link(5, 4, pose(0.3, 0, 0, 0)));  // 5: refused by the edge (never in its map)
  EdgeKeyFrames edge;
  KeyFramePose kf4;
  kf4.id = 4;
  kf4.T_wc = pose(2, 0, 1, 0.5);
  edge.in_map.push_back(kf4);
  mobile.frames.push_back(frame(7.0, 5, pose(0, 0, 0.1, 0)));
  const ComposedTrajectory t = split_composer(mobile, edge).compose(mobile.frames);
  ASSERT_EQ(t.poses.size(), 1u);
  EXPECT_TRUE(t.poses[0].second.isApprox(kf4.T_wc * pose(0.3, 0, 0, 0) * pose(0, 0, 0.1, 0), 1e-12));
}

TEST(SplitComposer, TheEdgesCulledRelationReplacesTheMobiles) {
  MobileAnchors mobile;
  mobile.keyframes.push_back(link(5, 4, pose(9, 9, 9, 0)));  // as tracked: before any correction
  EdgeKeyFrames edge;
  KeyFramePose kf3;
  kf3.id = 3;
  kf3.T_wc = pose(1, 1, 1, 0);
  edge.in_map.push_back(kf3);
  edge.culled.push_back(link(5, 3, pose(0.2, 0, 0, 0)));  // the edge re-parented 5 on 3, then culled it
  const std::optional<Eigen::Isometry3d> T_w5 = split_composer(mobile, edge).keyframe_pose(5);
  ASSERT_TRUE(T_w5.has_value());
  EXPECT_TRUE(T_w5->isApprox(kf3.T_wc * pose(0.2, 0, 0, 0), 1e-12));
}

TEST(AnchorFiles, WrittenLinesReadBack) {
  const std::string anchors = ::testing::TempDir() + "anchors_roundtrip.txt";
  const std::string keyframes = ::testing::TempDir() + "keyframes_roundtrip.txt";
  {
    std::ofstream out(anchors);
    out << anchors_file_header();
    write_anchor(out, link(2, 1, pose(0.1, 0.2, 0.3, 0.4)));
    write_anchor(out, frame(1305031102.175304, 2, pose(0.01, 0, 0, -0.1)));
  }
  EdgeKeyFrames edge;
  KeyFramePose kf;
  kf.id = 1;
  kf.stamp = 1305031102.1;
  kf.T_wc = pose(1, 2, 3, 0.5);
  edge.in_map.push_back(kf);
  edge.culled.push_back(link(2, 1, pose(0.1, 0.2, 0.3, 0.4)));
  std::ofstream(keyframes) << edge_keyframes_text(edge);

  const MobileAnchors m = read_mobile_anchors(anchors);
  const EdgeKeyFrames e = read_edge_keyframes(keyframes);
  ASSERT_EQ(m.frames.size(), 1u);
  ASSERT_EQ(m.keyframes.size(), 1u);
  EXPECT_NEAR(m.frames[0].stamp, 1305031102.175304, 1e-6);
  EXPECT_EQ(m.frames[0].reference_id, 2u);
  EXPECT_TRUE(m.keyframes[0].T_parent_kf.isApprox(pose(0.1, 0.2, 0.3, 0.4), 1e-6));
  ASSERT_EQ(e.in_map.size(), 1u);
  ASSERT_EQ(e.culled.size(), 1u);
  EXPECT_EQ(e.culled[0].parent_id, 1u);
  EXPECT_TRUE(e.in_map[0].T_wc.isApprox(kf.T_wc, 1e-6));
  std::remove(anchors.c_str());
  std::remove(keyframes.c_str());
}

TEST(AnchorFiles, AMalformedLineNamesTheFileAndLine) {
  const std::string path = ::testing::TempDir() + "anchors_bad.txt";
  std::ofstream(path) << "# header\nF 1.0 2 0 0 0 0 0 0 1\nF 1.0 2 0 0 0 0 0 0\n";
  try {
    read_mobile_anchors(path);
    FAIL() << "a short F line must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "1 1.0 0 0 0 0 0 0 0\n";  // a null rotation
  EXPECT_THROW(read_edge_keyframes(path), std::runtime_error);
  EXPECT_THROW(read_mobile_anchors("/nonexistent/anchors.txt"), std::runtime_error);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace edge_slam
