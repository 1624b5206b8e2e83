// The TUM-format sequence writer: layout, headers, stamps, reproducibility, atomic output, and
// that the TUM reader reads back what it wrote.
#include "edge_slam/io/tum_dataset.h"
#include "edge_slam/sim/tum_sequence_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace edge_slam;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class SynthWriter : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(::testing::TempDir()) / ("edge_slam_synth_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    options_.max_frames = 3;
    options_.texels_per_m = 32;  // layout and bytes matter here, not texture detail
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
  SequenceOptions options_;
};

}  // namespace

TEST_F(SynthWriter, WritesATumFolderThatReadsBack) {
  const fs::path out = root_ / "seq";
  const SequenceReport report = write_tum_sequence(out.string(), options_);
  EXPECT_EQ(report.frames, 3);
  EXPECT_FALSE(fs::exists(root_ / "seq.tmp"));
  for (const char* f : {"rgb.txt", "depth.txt", "groundtruth.txt", "associations.txt", "camera.yaml"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_EQ(slurp(out / "rgb.txt"),
            "# color images\n# file: 'edge_slam_synth seed 42'\n# timestamp filename\n"
            "1000000000.000000 rgb/1000000000.000000.png\n1000000000.033333 rgb/1000000000.033333.png\n"
            "1000000000.066667 rgb/1000000000.066667.png\n");
  const std::string assoc = slurp(out / "associations.txt");
  EXPECT_EQ(assoc.substr(0, assoc.find('\n')),
            "1000000000.000000 rgb/1000000000.000000.png 1000000000.000000 depth/1000000000.000000.png");

  const TumDataset ds = TumDataset::open(out.string());
  ASSERT_EQ(ds.size(), 3u);
  ASSERT_EQ(ds.ground_truth().size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(ds.frames()[i].rgb_stamp, ds.frames()[i].depth_stamp);
    EXPECT_EQ(ds.frames()[i].rgb_stamp, ds.ground_truth()[i].first);
  }
  EXPECT_EQ(ds.load_rgb(2).size(), cv::Size(640, 480));
  const cv::Mat depth = ds.load_depth_metres(1);
  EXPECT_GT(depth.at<float>(240, 320), 0.5f);
  // Ground truth is the trajectory's pose at the frame time.
  const Eigen::Isometry3d expected = Trajectory(42).pose_at(1.0 / 30.0);
  EXPECT_LT((ds.ground_truth()[1].second.translation() - expected.translation()).norm(), 1e-8);
  EXPECT_LT((ds.ground_truth()[1].second.linear() - expected.linear()).norm(), 1e-8);
}

TEST_F(SynthWriter, SameSeedSameBytesAndReplacesOnlyItsOwnOutput) {
  write_tum_sequence((root_ / "a").string(), options_);
  write_tum_sequence((root_ / "b").string(), options_);
  for (const auto& entry : fs::recursive_directory_iterator(root_ / "a")) {
    if (!entry.is_regular_file()) continue;
    const fs::path rel = fs::relative(entry.path(), root_ / "a");
    EXPECT_EQ(slurp(entry.path()), slurp(root_ / "b" / rel)) << rel;
  }
  // Re-running over an earlier output replaces it...
  options_.max_frames = 1;
  write_tum_sequence((root_ / "a").string(), options_);
  EXPECT_EQ(TumDataset::open((root_ / "a").string()).size(), 1u);
  // ...but any other existing folder is left alone.
  fs::create_directories(root_ / "precious");
  std::ofstream(root_ / "precious" / "notes.txt") << "keep";
  EXPECT_THROW(write_tum_sequence((root_ / "precious").string(), options_), std::runtime_error);
  EXPECT_TRUE(fs::exists(root_ / "precious" / "notes.txt"));
  EXPECT_FALSE(fs::exists(root_ / "precious.tmp"));
}

TEST_F(SynthWriter, FrameCounts) {
  SequenceOptions o;
  EXPECT_EQ(sequence_frame_count(o), 901);
  EXPECT_EQ(sequence_frame_count(SequenceOptions::long_variant(42)), 10801);
  o.fps = 15;
  EXPECT_EQ(sequence_frame_count(o), 451);
}
