// Local bundle adjustment benchmark: times run_local_bundle_adjustment on synthetic problems
// shaped like the windows of an RGB-D sequence (fr1_rpy ends with ~50 free keyframes, ~20
// fixed, ~4000 points and ~20000 observations). Reports thread CPU time, which the other
// jobs sharing the machine do not inflate, next to wall time (with --threads > 1 the cpu
// figure counts the calling thread only).
//
//   local_ba_benchmark [--free 50] [--fixed 20] [--points 4000] [--views 5] [--mono 0.15]
//                      [--outliers 0.05] [--repeat 5] [--threads 1]
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "edge_slam/optimize/local_bundle_adjustment.h"

using namespace edge_slam;

namespace {

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct Shape {
  int free_kfs = 50, fixed_kfs = 20, points = 4000, views = 5, repeat = 5, threads = 1;
  double mono = 0.15, outliers = 0.05;
};

PinholeCamera tum_like_camera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 517.3;
  c.fy = 516.5;
  c.cx = 318.6;
  c.cy = 255.3;
  c.bf = 40.0;
  c.th_depth = 3.1;
  return c;
}

// Keyframes on a small arc looking at a wall of points 1-3 m away (a room-sized scene); the
// estimates are perturbed (2 cm, ~0.5 deg, points 1 cm) and some pixels are gross outliers.
BundleAdjustmentProblem make_problem(const Shape& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  BundleAdjustmentProblem p;
  p.camera = tum_like_camera();
  const int num_kfs = s.free_kfs + s.fixed_kfs;
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < num_kfs; ++k) {
    const double a = 0.6 * (k / double(std::max(1, num_kfs - 1)) - 0.5);
    Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
    T_wc.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_wc.translation() = Eigen::Vector3d(0.5 * a, 0.05 * n01(rng), 0.0);
    truth.push_back(T_wc.inverse());
    BaKeyFrame kf;
    kf.id = static_cast<uint32_t>(k);
    kf.fixed = k >= s.free_kfs;
    Eigen::Isometry3d noisy = truth.back();
    if (!kf.fixed) {
      noisy.linear() = (Eigen::AngleAxisd(0.008 * n01(rng), Eigen::Vector3d::UnitX()) *
                        Eigen::AngleAxisd(0.008 * n01(rng), Eigen::Vector3d::UnitY()))
                           .toRotationMatrix() *
                       noisy.linear();
      noisy.translation() += 0.02 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    }
    kf.T_cw = noisy;
    p.keyframes.push_back(kf);
  }
  std::uniform_int_distribution<int> pick_kf(0, num_kfs - 1);
  for (int i = 0; i < s.points; ++i) {
    const int anchor = pick_kf(rng);
    const Eigen::Isometry3d T_wc = truth[anchor].inverse();
    const double z = 1.0 + 2.0 * u01(rng);
    const Eigen::Vector3d pc((u01(rng) - 0.5) * z, (u01(rng) - 0.5) * 0.75 * z, z);
    const Eigen::Vector3d pw = T_wc * pc;
    BaPoint bp;
    bp.id = static_cast<uint32_t>(i);
    bp.position = pw + 0.01 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    p.points.push_back(bp);
    std::map<int, bool> seen;
    for (int v = 0; v < s.views * 3 && static_cast<int>(seen.size()) < s.views; ++v) {
      const int k = v == 0 ? anchor : std::clamp(anchor + static_cast<int>(4 * n01(rng)), 0, num_kfs - 1);
      if (seen.count(k)) continue;
      const Eigen::Vector3d c = truth[k] * pw;
      if (c.z() < 0.3) continue;
      seen[k] = true;
      BaObservation o;
      o.keyframe_id = static_cast<uint32_t>(k);
      o.point_id = bp.id;
      const int level = static_cast<int>(u01(rng) * 4);
      const double sigma = std::pow(1.2, level);
      o.inv_sigma2 = 1.0 / (sigma * sigma);
      o.pixel = p.camera.project(c) + sigma * Eigen::Vector2d(n01(rng), n01(rng));
      if (u01(rng) < s.outliers) o.pixel += Eigen::Vector2d(30.0, -25.0);
      o.right_x = u01(rng) < s.mono ? -1.0 : o.pixel.x() - p.camera.bf / c.z();
      p.observations.push_back(o);
    }
  }
  return p;
}

int usage() {
  std::cerr << "usage: local_ba_benchmark [--free N] [--fixed N] [--points N] [--views N] [--mono F]\n"
               "                          [--outliers F] [--repeat N] [--threads N]\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  Shape s;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage(), 0;
    if (i + 1 >= argc) return usage();
    const std::string v = argv[++i];
    try {
      if (a == "--free") s.free_kfs = std::stoi(v);
      else if (a == "--fixed") s.fixed_kfs = std::stoi(v);
      else if (a == "--points") s.points = std::stoi(v);
      else if (a == "--views") s.views = std::stoi(v);
      else if (a == "--mono") s.mono = std::stod(v);
      else if (a == "--outliers") s.outliers = std::stod(v);
      else if (a == "--repeat") s.repeat = std::stoi(v);
      else if (a == "--threads") s.threads = std::stoi(v);
      else return usage();
    } catch (const std::exception&) {
      std::cerr << "local_ba_benchmark: bad value '" << v << "' for " << a << "\n";
      return 1;
    }
  }
  if (s.free_kfs < 1 || s.fixed_kfs < 0 || s.points < 1 || s.views < 2 || s.repeat < 1 || s.threads < 1) return usage();

  std::vector<double> cpu, wall;
  size_t observations = 0;
  BundleAdjustmentResult last;
  for (int r = 0; r < s.repeat; ++r) {
    const BundleAdjustmentProblem problem = make_problem(s, 11u + static_cast<unsigned>(r));
    observations = problem.observations.size();
    LocalBaOptions options;
    options.num_threads = s.threads;
    const double c0 = thread_cpu_ms();
    const auto w0 = std::chrono::steady_clock::now();
    last = run_local_bundle_adjustment(problem, options);
    wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count());
    cpu.push_back(thread_cpu_ms() - c0);
    if (!last.ok) {
      std::cerr << "local_ba_benchmark: BA failed: " << last.message << "\n";
      return 1;
    }
  }
  std::sort(cpu.begin(), cpu.end());
  std::sort(wall.begin(), wall.end());
  std::printf("local BA: %d free + %d fixed keyframes, %d points, %zu observations, %d thread(s)\n", s.free_kfs,
              s.fixed_kfs, s.points, observations, s.threads);
  std::printf("  thread cpu ms: median %.1f min %.1f max %.1f | wall ms: median %.1f (over %d runs)\n",
              cpu[cpu.size() / 2], cpu.front(), cpu.back(), wall[wall.size() / 2], s.repeat);
  std::printf("  last run: %d iterations, %zu outlier observations, cost %.0f -> %.0f\n", last.iterations,
              last.outlier_observations.size(), last.initial_cost, last.final_cost);
  return 0;
}
