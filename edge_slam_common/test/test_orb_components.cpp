// Building blocks of the extractor: feature budget, orientation disc, test pattern,
// quadtree distribution, grid FAST and intensity-centroid angle.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "edge_slam/feature/brief_pattern.h"
#include "edge_slam/feature/fast_grid_detector.h"
#include "edge_slam/feature/intensity_centroid.h"
#include "edge_slam/feature/orb_patch.h"
#include "edge_slam/feature/pyramid_scales.h"
#include "edge_slam/feature/quadtree_distribution.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

TEST(OrbComponents, FeatureBudgetSumsToTotalAndShrinksWithLevel) {
  for (int total : {0, 1, 7, 500, 1000, 2000}) {
    const std::vector<int> counts = features_per_level(total, 1.2f, 8);
    int sum = 0;
    for (int c : counts) {
      EXPECT_GE(c, 0);
      sum += c;
    }
    EXPECT_EQ(sum, total);
  }
  const std::vector<int> counts = features_per_level(1000, 1.2f, 8);
  for (size_t i = 1; i + 1 < counts.size(); ++i) EXPECT_LT(counts[i], counts[i - 1]);
  EXPECT_EQ(features_per_level(1000, 1.2f, 1), std::vector<int>{1000});
}

TEST(OrbComponents, DiscHalfWidthsDescribeAnExactDisc) {
  const std::vector<int> hw = disc_half_widths(kOrbPatchRadius);
  ASSERT_EQ(hw.size(), static_cast<size_t>(kOrbPatchRadius + 1));
  EXPECT_EQ(hw[0], kOrbPatchRadius);
  int area = 0;
  for (int v = -kOrbPatchRadius; v <= kOrbPatchRadius; ++v)
    for (int u = -kOrbPatchRadius; u <= kOrbPatchRadius; ++u) {
      const bool inside = u * u + v * v <= kOrbPatchRadius * kOrbPatchRadius;
      EXPECT_EQ(inside, std::abs(u) <= hw[std::abs(v)]);
      // Symmetric under swapping u and v, so a 90-degree turn maps the disc onto itself.
      EXPECT_EQ(std::abs(u) <= hw[std::abs(v)], std::abs(v) <= hw[std::abs(u)]);
      area += inside;
    }
  EXPECT_EQ(area, 709);
}

TEST(OrbComponents, PatternStaysInsideThePatchAndHasNoDegenerateTests) {
  std::set<std::tuple<int, int, int, int>> seen;
  for (const BriefTest& t : brief_pattern()) {
    EXPECT_LE(t.x1 * t.x1 + t.y1 * t.y1, kOrbPatchRadius * kOrbPatchRadius);
    EXPECT_LE(t.x2 * t.x2 + t.y2 * t.y2, kOrbPatchRadius * kOrbPatchRadius);
    EXPECT_FALSE(t.x1 == t.x2 && t.y1 == t.y2);
    EXPECT_TRUE(seen.insert({t.x1, t.y1, t.x2, t.y2}).second) << "duplicate test";
  }
  // Rotated, rounded points must stay within the border kept free around keypoints.
  EXPECT_LE(kOrbPatchRadius + 1 + 3, kOrbEdgeBorder);
}

TEST(OrbComponents, QuadtreeKeepsIsolatedKeypointsOverDenseClusters) {
  std::vector<cv::KeyPoint> kps;
  // A dense, strong cluster in the top-left corner ...
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 30; ++x) kps.emplace_back(cv::Point2f(10.f + x, 10.f + y), 7.f, -1.f, 100.f);
  // ... and eight weak keypoints spread over the rest.
  const cv::Point2f spread[] = {{500, 50}, {300, 300}, {600, 400}, {100, 400}, {400, 200}, {250, 100}, {550, 250}, {50, 250}};
  for (const cv::Point2f& p : spread) kps.emplace_back(p, 7.f, -1.f, 1.f);

  const std::vector<cv::KeyPoint> kept = distribute_quadtree(kps, cv::Rect2f(0, 0, 640, 480), 20);
  EXPECT_LE(kept.size(), 20u);
  EXPECT_GE(kept.size(), 16u);
  int weak = 0;
  for (const cv::KeyPoint& kp : kept) weak += kp.response == 1.f;
  EXPECT_EQ(weak, 8);
}

TEST(OrbComponents, QuadtreeKeepsStrongestPerCellAndHandlesEdgeCases) {
  std::vector<cv::KeyPoint> kps = {cv::KeyPoint(cv::Point2f(100, 100), 7.f, -1.f, 5.f),
                                   cv::KeyPoint(cv::Point2f(101, 100), 7.f, -1.f, 9.f),
                                   cv::KeyPoint(cv::Point2f(100, 101), 7.f, -1.f, 3.f)};
  const std::vector<cv::KeyPoint> one = distribute_quadtree(kps, cv::Rect2f(0, 0, 640, 480), 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].response, 9.f);
  EXPECT_EQ(distribute_quadtree(kps, cv::Rect2f(0, 0, 640, 480), 10).size(), 3u);
  EXPECT_TRUE(distribute_quadtree(kps, cv::Rect2f(0, 0, 640, 480), 0).empty());
  EXPECT_TRUE(distribute_quadtree({}, cv::Rect2f(0, 0, 640, 480), 10).empty());
  // Duplicated positions and points outside the region terminate and are kept at most once each.
  std::vector<cv::KeyPoint> dup(50, cv::KeyPoint(cv::Point2f(5, 5), 7.f));
  dup.emplace_back(cv::Point2f(-20, 900), 7.f);
  EXPECT_EQ(distribute_quadtree(dup, cv::Rect2f(0, 0, 640, 480), 10).size(), 2u);
}

TEST(OrbComponents, GridFastRespectsBorderAndRetriesFlatCells) {
  cv::Mat image = make_synthetic_texture(cv::Size(320, 240), 2);
  // Lower the contrast of the right half so only the low threshold finds corners there.
  cv::Mat right = image(cv::Rect(160, 0, 160, 240));
  right.convertTo(right, CV_8U, 0.12, 100);
  FastGridParams params;
  const std::vector<cv::KeyPoint> corners = detect_fast_in_grid(image, params);
  const cv::Rect area = fast_detection_area(image.size(), params.border);
  int right_side = 0;
  for (const cv::KeyPoint& kp : corners) {
    EXPECT_TRUE(area.contains(cv::Point(cvRound(kp.pt.x), cvRound(kp.pt.y))));
    right_side += kp.pt.x >= 180;
  }
  FastGridParams no_retry = params;
  no_retry.min_threshold = no_retry.ini_threshold;
  int right_without_retry = 0;
  for (const cv::KeyPoint& kp : detect_fast_in_grid(image, no_retry)) right_without_retry += kp.pt.x >= 180;
  EXPECT_GE(right_side, 10);
  EXPECT_GE(right_side, 2 * right_without_retry);
}

TEST(OrbComponents, IntensityCentroidPointsTowardsTheBrightSide) {
  const std::vector<int> hw = disc_half_widths(kOrbPatchRadius);
  // Bright half-plane in direction theta (image coordinates, y down) -> angle theta.
  for (int theta_deg : {0, 45, 90, 135, 180, 270, 300}) {
    cv::Mat image(64, 64, CV_8UC1);
    const double t = theta_deg * CV_PI / 180.0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x)
        image.at<uint8_t>(y, x) = ((x - 32) * std::cos(t) + (y - 32) * std::sin(t)) > 0.25 ? 200 : 20;
    float angle = intensity_centroid_angle(image, 32, 32, hw);
    double diff = std::fmod(angle - theta_deg + 540.0, 360.0) - 180.0;
    EXPECT_NEAR(diff, 0.0, 3.0) << "theta " << theta_deg;
  }
}

TEST(OrbComponents, CentroidDiscGivesTheScalarAngleExactly) {
  // The SIMD moments (radius 15) and the scalar fallback (other radii) against the plain loop:
  // the same integer moments, hence bit-identical angles, on texture, noise and saturated pixels.
  cv::Mat noise(120, 160, CV_8UC1);
  cv::randu(noise, 0, 256);
  cv::Mat saturated(120, 160, CV_8UC1, cv::Scalar(255));
  saturated(cv::Rect(0, 0, 80, 120)).setTo(0);
  const std::vector<cv::Mat> images = {make_synthetic_texture(cv::Size(160, 120), 3), noise, saturated};
  for (int radius : {kOrbPatchRadius, 7, 20}) {
    const CentroidDisc disc(radius);
    ASSERT_EQ(disc.half_widths(), disc_half_widths(radius));
    int compared = 0;
    for (const cv::Mat& image : images)
      for (int y = radius + 1; y < image.rows - radius - 1; y += 7)
        for (int x = std::max(radius, 16) + 1; x < image.cols - std::max(radius, 16) - 1; x += 5, ++compared)
          ASSERT_EQ(disc.angle(image, x, y), intensity_centroid_angle(image, x, y, disc.half_widths()))
              << "radius " << radius << " at " << x << "," << y;
    EXPECT_GT(compared, 500);
  }
}
