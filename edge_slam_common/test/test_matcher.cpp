// Matching on synthetic projections: known correspondences, descriptor noise, wrong
// keypoint orientations that the rotation histogram must reject.
#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "edge_slam/match/orb_matcher.h"
#include "edge_slam/match/rotation_histogram.h"

using namespace edge_slam;

namespace {

PinholeCamera camera() {
  PinholeCamera c = synthetic_room_camera(30.0);
  c.fx = c.fy = 500;
  c.th_depth = 3.2;
  return c;
}

struct Scene {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> octave;
  cv::Mat descriptors;  // one per point
  std::vector<std::shared_ptr<MapPoint>> mps;
};

Scene make_scene(std::mt19937& rng, int n) {
  Scene s;
  std::uniform_real_distribution<double> ux(-2, 2), uy(-1.5, 1.5), uz(3, 6);
  std::uniform_int_distribution<int> uo(0, 2);
  s.descriptors.create(n, 32, CV_8U);
  cv::randu(s.descriptors, 0, 256);
  const auto pyr = ScalePyramid::make(8, 1.2f);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p(ux(rng), uy(rng), uz(rng));
    s.points.push_back(p);
    s.octave.push_back(uo(rng));
    auto mp = std::make_shared<MapPoint>(i, p, 0);
    mp->set_descriptor(s.descriptors.ptr<uint8_t>(i));
    const float dist = static_cast<float>(p.norm());
    // Half a level below the next boundary so that small motions keep the predicted level.
    const float max_d = dist * std::pow(1.2f, s.octave.back() - 0.5f);
    mp->set_normal_and_distances(p.normalized(), max_d / pyr.scale_factors[7], max_d);
    mp->add_observation(0, i);
    s.mps.push_back(mp);
  }
  return s;
}

// Frame seeing the scene from T_cw: keypoint k <-> scene point point_of[k]. Descriptors get
// `flips` random bit flips; angles are 30 degrees plus `angle_offset` for listed points.
Frame observe(const Scene& s, const Eigen::Isometry3d& T_cw, std::mt19937& rng, int flips,
              std::vector<int>& point_of, const std::set<int>& rotated = {}, uint64_t id = 1) {
  const PinholeCamera cam = camera();
  auto f = std::make_shared<FrameFeatures>();
  f->camera = cam;
  f->pyramid = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  std::normal_distribution<float> noise(0.f, 0.3f);
  std::uniform_int_distribution<int> ubyte(0, 31), ubit(0, 7);
  point_of.clear();
  std::vector<cv::Mat> rows;
  for (size_t i = 0; i < s.points.size(); ++i) {
    const Eigen::Vector3d pc = T_cw * s.points[i];
    const Eigen::Vector2d uv = cam.project(pc);
    if (uv.x() < 5 || uv.y() < 5 || uv.x() > 635 || uv.y() > 475) continue;
    cv::KeyPoint kp(static_cast<float>(uv.x()) + noise(rng), static_cast<float>(uv.y()) + noise(rng), 31.f,
                    rotated.count(static_cast<int>(i)) ? 90.f + (i * 37) % 240 : 30.f, 1.f, s.octave[i]);
    f->keys.push_back(kp);
    f->depth.push_back(static_cast<float>(pc.z()));
    f->right_x.push_back(static_cast<float>(kp.pt.x - cam.bf / pc.z()));
    cv::Mat d = s.descriptors.row(static_cast<int>(i)).clone();
    for (int k = 0; k < flips; ++k) d.at<uint8_t>(0, ubyte(rng)) ^= static_cast<uint8_t>(1 << ubit(rng));
    rows.push_back(d);
    point_of.push_back(static_cast<int>(i));
  }
  cv::vconcat(rows, f->descriptors);
  f->keys_un = f->keys;
  f->bounds = compute_image_bounds(cam);
  f->grid = FeatureGrid(f->keys_un, f->bounds);
  Frame frame(id, 0.0, f);
  frame.set_pose(T_cw);
  return frame;
}

Eigen::Isometry3d small_motion() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.03, -0.01, 0.02);
  return T;
}

// Counts matched keypoints and how many of them are wrong.
void check(const Frame& f, const std::vector<int>& point_of, int& matched, int& wrong) {
  matched = wrong = 0;
  for (size_t k = 0; k < f.map_points.size(); ++k) {
    if (!f.map_points[k]) continue;
    ++matched;
    if (static_cast<int>(f.map_points[k]->id()) != point_of[k]) ++wrong;
  }
}

}  // namespace

TEST(RotationHistogram, KeepsThreeLargestBins) {
  RotationHistogram h;
  int idx = 0;
  for (int i = 0; i < 50; ++i) h.add(40.f, 10.f, idx++);   // 30 deg
  for (int i = 0; i < 20; ++i) h.add(10.f, 350.f, idx++);  // 20 deg (wraps)
  for (int i = 0; i < 10; ++i) h.add(0.f, 0.f, idx++);     // 0 deg
  for (int i = 0; i < 3; ++i) h.add(180.f, 0.f, idx++);    // 180 deg: fourth bin, rejected
  const auto bad = h.inconsistent();
  EXPECT_EQ(bad, std::vector<int>({80, 81, 82}));
}

TEST(Matcher, LastFrameProjectionFindsCorrectMatches) {
  std::mt19937 rng(3);
  const Scene s = make_scene(rng, 400);
  std::vector<int> last_of, cur_of;
  Frame last = observe(s, Eigen::Isometry3d::Identity(), rng, 0, last_of, {}, 0);
  for (size_t k = 0; k < last.size(); ++k) last.map_points[k] = s.mps[last_of[k]];
  Frame cur = observe(s, small_motion(), rng, 6, cur_of);
  // Pose guess a little off the truth, as from a motion model.
  Eigen::Isometry3d guess = small_motion();
  guess.translation() += Eigen::Vector3d(0.005, 0.004, -0.003);
  cur.set_pose(guess);
  const int n = OrbMatcher(0.9f, true).search_by_projection(cur, last, 7);
  int matched, wrong;
  check(cur, cur_of, matched, wrong);
  EXPECT_EQ(n, matched);
  EXPECT_GT(matched, 0.9 * cur.size());
  EXPECT_EQ(wrong, 0);
}

TEST(Matcher, RotationHistogramRejectsInconsistentOrientations) {
  std::mt19937 rng(4);
  const Scene s = make_scene(rng, 400);
  std::set<int> rotated;
  for (int i = 0; i < 400; i += 5) rotated.insert(i);  // 20% with scattered angle errors
  std::vector<int> last_of, cur_of;
  Frame last = observe(s, Eigen::Isometry3d::Identity(), rng, 0, last_of, {}, 0);
  for (size_t k = 0; k < last.size(); ++k) last.map_points[k] = s.mps[last_of[k]];
  Frame cur = observe(s, small_motion(), rng, 6, cur_of, rotated);
  OrbMatcher(0.9f, true).search_by_projection(cur, last, 7);
  int rotated_matched = 0, straight_matched = 0, straight = 0;
  for (size_t k = 0; k < cur.size(); ++k) {
    const bool rot = rotated.count(cur_of[k]) > 0;
    if (!rot) ++straight;
    if (!cur.map_points[k]) continue;
    (rot ? rotated_matched : straight_matched)++;
  }
  EXPECT_EQ(rotated_matched, 0);
  EXPECT_GT(straight_matched, 0.9 * straight);
  // Without the check they would be matched.
  Frame cur2 = observe(s, small_motion(), rng, 6, cur_of, rotated);
  OrbMatcher(0.9f, false).search_by_projection(cur2, last, 7);
  int matched2 = 0;
  for (size_t k = 0; k < cur2.size(); ++k) matched2 += (cur2.map_points[k] && rotated.count(cur_of[k])) ? 1 : 0;
  EXPECT_GT(matched2, 0);
}

TEST(Matcher, LocalMapProjectionUsesPredictedScaleAndRatio) {
  std::mt19937 rng(5);
  const Scene s = make_scene(rng, 400);
  std::vector<int> cur_of;
  Frame cur = observe(s, small_motion(), rng, 6, cur_of);
  std::vector<ProjectedPoint> projected;
  for (const auto& mp : s.mps) {
    ProjectedPoint p;
    if (project_into_frame(cur, mp, 0.5f, p)) {
      EXPECT_EQ(p.level, s.octave[mp->id()]);
      projected.push_back(p);
    }
  }
  EXPECT_GT(projected.size(), 0.9 * cur.size());
  const int n = OrbMatcher(0.8f, true).search_by_projection(cur, projected, 3);
  int matched, wrong;
  check(cur, cur_of, matched, wrong);
  EXPECT_EQ(n, matched);
  EXPECT_GT(matched, 0.9 * cur.size());
  EXPECT_EQ(wrong, 0);

  // A point behind the camera or outside its distance range is not predicted visible.
  auto behind = std::make_shared<MapPoint>(999, Eigen::Vector3d(0, 0, -3), 0);
  behind->set_normal_and_distances(Eigen::Vector3d(0, 0, 1), 0.1f, 100.f);
  ProjectedPoint p;
  EXPECT_FALSE(project_into_frame(cur, behind, 0.5f, p));
  auto far = std::make_shared<MapPoint>(998, Eigen::Vector3d(0, 0, 50), 0);
  far->set_normal_and_distances(Eigen::Vector3d(0, 0, 1), 1.f, 10.f);
  EXPECT_FALSE(project_into_frame(cur, far, 0.5f, p));
}

TEST(Matcher, BowSearchMatchesWithinNodes) {
  std::mt19937 rng(6);
  const Scene s = make_scene(rng, 300);
  std::vector<int> kf_of, cur_of;
  Frame kf_frame = observe(s, Eigen::Isometry3d::Identity(), rng, 0, kf_of, {}, 0);
  Frame cur = observe(s, small_motion(), rng, 6, cur_of);
  // Vocabulary nodes: point id mod 40, as a trained vocabulary would group similar features.
  FeatureVector fv_kf, fv_cur;
  for (size_t k = 0; k < kf_of.size(); ++k) fv_kf[kf_of[k] % 40].push_back(static_cast<uint32_t>(k));
  for (size_t k = 0; k < cur_of.size(); ++k) fv_cur[cur_of[k] % 40].push_back(static_cast<uint32_t>(k));
  auto kf = std::make_shared<KeyFrame>(0, kf_frame);
  kf->set_bow({{1, 1.0}}, fv_kf);
  cur.set_bow({{1, 1.0}}, fv_cur);
  std::vector<std::shared_ptr<MapPoint>> kf_points(kf_of.size());
  for (size_t k = 0; k < kf_of.size(); ++k) kf_points[k] = s.mps[kf_of[k]];
  const int n = OrbMatcher(0.7f, true).search_by_bow(*kf, kf_points, cur);
  int matched, wrong;
  check(cur, cur_of, matched, wrong);
  EXPECT_EQ(n, matched);
  EXPECT_GT(matched, 0.9 * std::min(kf_of.size(), cur_of.size()));
  EXPECT_EQ(wrong, 0);
}
