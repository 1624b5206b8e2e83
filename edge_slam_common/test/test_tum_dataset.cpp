// TUM folder reader: parsing, association like associate.py, clear errors with file:line,
// on-demand image loading; plus the real fr1_rpy sequence when the shared datasets exist.
#include "edge_slam/io/tum_dataset.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

using namespace edge_slam;
namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// Expects fn to throw std::runtime_error whose message contains every one of `parts`.
void expect_error(const std::function<void()>& fn, const std::vector<std::string>& parts) {
  try {
    fn();
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    for (const std::string& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

class TinyTumFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("edge_slam_tum_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "rgb");
    fs::create_directories(dir_ / "depth");
    write_file(dir_ / "rgb.txt",
               "# color images\n# file: 'tiny'\n# timestamp filename\n"
               "1.000000 rgb/1.000000.png\n1.033000 rgb/1.033000.jpg\n1.066000 rgb/1.066000.png\n"
               "1.500000 rgb/1.500000.png\n");
    // 1.040 is nearest to 1.033 (7 ms) and also within 20 ms of... nothing else; 1.070 belongs
    // to 1.066; 1.010 to 1.000; 1.300 matches nothing; 1.500 has no depth near it.
    write_file(dir_ / "depth.txt",
               "# depth maps\n# file: 'tiny'\n# timestamp filename\n"
               "1.010000 depth/1.010000.png\n1.040000 depth/1.040000.png\n"
               "1.070000 depth/1.070000.png\n1.300000 depth/1.300000.png\n");
    write_file(dir_ / "groundtruth.txt",
               "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
               "0.99 1 2 3 0 0 0 1\n1.02 1 2 3.5 0 0 0.7071068 0.7071068\n");
    const cv::Mat colour(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
    cv::imwrite((dir_ / "rgb/1.000000.png").string(), colour);
    cv::imwrite((dir_ / "rgb/1.033000.jpg").string(), colour);
    cv::imwrite((dir_ / "rgb/1.066000.png").string(), colour);
    const cv::Mat depth(48, 64, CV_16UC1, cv::Scalar(10000));  // 2 m
    cv::imwrite((dir_ / "depth/1.010000.png").string(), depth);
    cv::imwrite((dir_ / "depth/1.040000.png").string(), depth);
    cv::imwrite((dir_ / "depth/1.070000.png").string(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(7)));
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

}  // namespace

TEST_F(TinyTumFolder, ParsesAndAssociatesLikeAssociatePy) {
  const TumDataset ds = TumDataset::open(dir_.string());
  EXPECT_EQ(ds.rgb_list().size(), 4u);
  EXPECT_EQ(ds.depth_list().size(), 4u);
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_DOUBLE_EQ(ds.frames()[0].rgb_stamp, 1.0);
  EXPECT_DOUBLE_EQ(ds.frames()[0].depth_stamp, 1.01);
  EXPECT_DOUBLE_EQ(ds.frames()[1].depth_stamp, 1.04);
  EXPECT_DOUBLE_EQ(ds.frames()[2].depth_stamp, 1.07);
  EXPECT_EQ(ds.frames()[1].rgb_path, (dir_ / "rgb/1.033000.jpg").string());
  ASSERT_EQ(ds.ground_truth().size(), 2u);
  EXPECT_DOUBLE_EQ(ds.ground_truth()[1].first, 1.02);
  EXPECT_NEAR(ds.ground_truth()[1].second.translation().z(), 3.5, 1e-12);
  EXPECT_NEAR(ds.ground_truth()[1].second.linear()(1, 0), 1.0, 1e-6);  // 90 deg about z

  EXPECT_EQ(ds.load_rgb(1).type(), CV_8UC3);  // JPEG is fine
  const cv::Mat depth = ds.load_depth(0);
  EXPECT_EQ(depth.type(), CV_16UC1);
  EXPECT_FLOAT_EQ(ds.load_depth_metres(0).at<float>(5, 5), 2.0f);
}

TEST_F(TinyTumFolder, EachDepthIsUsedAtMostOnce) {
  // Two colour frames 4 ms apart compete for one depth frame: the nearer wins.
  const std::vector<TumListEntry> rgb = {{1.000, "a"}, {1.004, "b"}};
  const std::vector<TumListEntry> depth = {{1.003, "d"}};
  const auto pairs = associate_by_stamp(rgb, depth, 0.02);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].first, 1u);
}

TEST_F(TinyTumFolder, WrongImagesAreReportedByPath) {
  const TumDataset ds = TumDataset::open(dir_.string());
  expect_error([&] { ds.load_depth(2); }, {"1.070000.png", "16-bit"});
  fs::remove(dir_ / "rgb/1.066000.png");
  expect_error([&] { ds.load_rgb(2); }, {"cannot read colour image", "1.066000.png"});
}

TEST_F(TinyTumFolder, MalformedLinesNameFileAndLine) {
  write_file(dir_ / "rgb.txt", "# color images\n1.0 rgb/1.000000.png\nnot-a-stamp rgb/x.png\n");
  expect_error([&] { TumDataset::open(dir_.string()); }, {"rgb.txt:3", "not-a-stamp rgb/x.png"});
  write_file(dir_ / "rgb.txt", "1.0 rgb/1.000000.png\n");
  write_file(dir_ / "groundtruth.txt", "# gt\n1.0 1 2 3 0 0 0 1\n1.1 1 2 3 0 0 1\n");
  expect_error([&] { TumDataset::open(dir_.string()); }, {"groundtruth.txt:3", "1.1 1 2 3 0 0 1"});
  write_file(dir_ / "groundtruth.txt", "1.0 1 2 3 0 0 0 0\n");
  expect_error([&] { TumDataset::open(dir_.string()); }, {"groundtruth.txt:1", "zero quaternion"});
}

TEST_F(TinyTumFolder, MissingFolderOrListIsReported) {
  expect_error([&] { TumDataset::open((dir_ / "nope").string()); }, {"folder not found", "nope"});
  fs::remove(dir_ / "depth.txt");
  expect_error([&] { TumDataset::open(dir_.string()); }, {"depth.txt", "no such file"});
  // groundtruth.txt is optional (the benchmark's validation sequences have none).
  write_file(dir_ / "depth.txt", "1.01 depth/1.010000.png\n");
  fs::remove(dir_ / "groundtruth.txt");
  EXPECT_TRUE(TumDataset::open(dir_.string()).ground_truth().empty());
}

TEST(TumDatasetFr1Rpy, ReadsTheSharedSequence) {
  // Look for shared/datasets/tum_fr1_rpy in the working directory's ancestors.
  fs::path found;
  for (fs::path p = fs::current_path(); !p.empty(); p = p.parent_path()) {
    if (fs::is_directory(p / "shared/datasets/tum_fr1_rpy")) { found = p / "shared/datasets/tum_fr1_rpy"; break; }
    if (p == p.root_path()) break;
  }
  if (found.empty()) GTEST_SKIP() << "shared/datasets/tum_fr1_rpy not found above " << fs::current_path();
  const TumDataset ds = TumDataset::open(found.string());
  EXPECT_EQ(ds.rgb_list().size(), 723u);
  EXPECT_EQ(ds.depth_list().size(), 722u);
  EXPECT_GT(ds.size(), 680u);
  EXPECT_LT(ds.size(), 722u);
  EXPECT_EQ(ds.ground_truth().size(), 2742u);
  for (const TumFrame& f : ds.frames()) EXPECT_LT(std::abs(f.rgb_stamp - f.depth_stamp), 0.02);
  const cv::Mat rgb = ds.load_rgb(0), depth = ds.load_depth(0);
  EXPECT_EQ(rgb.size(), cv::Size(640, 480));
  EXPECT_EQ(depth.type(), CV_16UC1);
  std::cout << "fr1_rpy: " << ds.size() << " associated pairs\n";
}
