// The run recorder (io/run_recorder.h): the trajectory and anchors files are complete after
// flush() while the recorder still runs (and flushed on their own during a burst); metrics and
// KeyFrame files are whole files that read back; an uncreatable file is named at start.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "edge_slam/io/anchors_file.h"
#include "edge_slam/io/run_recorder.h"
#include "edge_slam/io/trajectory_io.h"
#include "support/csv_rows.h"

namespace edge_slam {
namespace {

std::string temp_path(const std::string& name) {
  return ::testing::TempDir() + "run_recorder_" + std::to_string(::getpid()) + "_" + name;
}

size_t data_lines(const std::string& path) {
  std::ifstream in(path);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

TEST(RunRecorder, TrajectoryAndAnchorsAreCompleteAfterAFlushWhileRunning) {
  RunFiles files;
  files.trajectory = temp_path("trajectory_online.txt");
  files.anchors = temp_path("anchors.txt");
  RunRecorder recorder(files);
  for (int i = 0; i < 3; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = 0.1 * i;
    recorder.pose(10.0 + i, T);
    recorder.anchor(FrameAnchor{10.0 + i, 7, T});
  }
  recorder.anchor(KeyFrameLink{7, 6, Eigen::Isometry3d::Identity()});
  recorder.flush();
  EXPECT_EQ(data_lines(files.trajectory), 3u);
  EXPECT_EQ(read_tum_trajectory(files.trajectory).size(), 3u);
  const MobileAnchors anchors = read_mobile_anchors(files.anchors);
  EXPECT_EQ(anchors.frames.size(), 3u);
  ASSERT_EQ(anchors.keyframes.size(), 1u);
  EXPECT_EQ(anchors.keyframes[0].parent_id, 6u);
  std::remove(files.trajectory.c_str());
  std::remove(files.anchors.c_str());
}

TEST(RunRecorder, ABurstOfPosesReachesTheFileWithoutAFlush) {
  RunFiles files;
  files.trajectory = temp_path("burst.txt");
  RunRecorder recorder(files);
  for (int i = 0; i < 2 * RunRecorder::kLinesPerFlush; ++i) recorder.pose(i, Eigen::Isometry3d::Identity());
  EXPECT_EQ(data_lines(files.trajectory), static_cast<size_t>(2 * RunRecorder::kLinesPerFlush));
  std::remove(files.trajectory.c_str());
}

TEST(RunRecorder, MetricsAndKeyFramesFilesAreWholeFiles) {
  RunFiles files;
  files.metrics = temp_path("metrics.json");
  files.keyframes = temp_path("keyframes.txt");
  RunRecorder recorder(files);
  MetricsJson m;
  m.integer("frames", 3);
  recorder.metrics(m);
  EdgeKeyFrames k;
  k.in_map.push_back(KeyFramePose{1, 5.0, Eigen::Isometry3d::Identity()});
  k.culled.push_back(KeyFrameLink{2, 1, Eigen::Isometry3d::Identity()});
  recorder.keyframes(k);
  recorder.keyframes(k);  // rewritten, not appended
  const std::string text = test_support::file_text(files.metrics);
  EXPECT_NE(text.find("\"frames\": 3"), std::string::npos) << text;
  const EdgeKeyFrames back = read_edge_keyframes(files.keyframes);
  EXPECT_EQ(back.in_map.size(), 1u);
  EXPECT_EQ(back.culled.size(), 1u);
  std::remove(files.metrics.c_str());
  std::remove(files.keyframes.c_str());
}

TEST(RunRecorder, NoPathsWriteNothingAndAnUncreatableFileIsNamed) {
  RunRecorder quiet{RunFiles{}};
  quiet.pose(1.0, Eigen::Isometry3d::Identity());
  quiet.metrics(MetricsJson());
  quiet.flush();
  RunFiles bad;
  bad.anchors = "/proc/no_such_dir/anchors.txt";
  try {
    RunRecorder recorder(bad);
    FAIL() << "an uncreatable file must be refused at start";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/no_such_dir"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edge_slam
