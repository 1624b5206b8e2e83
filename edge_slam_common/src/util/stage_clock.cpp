#include "edge_slam/util/stage_clock.h"

#include <time.h>

namespace edge_slam {
namespace {

thread_local StageClock* g_active = nullptr;

double thread_cpu_now_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
double wall_now_ms() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

}  // namespace

const char* to_string(TrackingStage s) {
  switch (s) {
    case TrackingStage::kExtract: return "extract";
    case TrackingStage::kMatch: return "match";
    case TrackingStage::kPose: return "pose";
    case TrackingStage::kLocalMap: return "local_map";
    case TrackingStage::kKeyFrame: return "keyframe";
    case TrackingStage::kCount: break;
  }
  return "?";
}

StageClock::StageClock(TrackingStage initial)
    : current_(initial), last_cpu_ms_(thread_cpu_now_ms()), last_wall_ms_(wall_now_ms()), previous_(g_active) {
  g_active = this;
}

StageClock::~StageClock() { g_active = previous_; }

StageClock* StageClock::active() { return g_active; }

void StageClock::charge() {
  const double cpu = thread_cpu_now_ms(), wall = wall_now_ms();
  const int k = static_cast<int>(current_);
  times_.cpu_ms[k] += cpu - last_cpu_ms_;
  times_.wall_ms[k] += wall - last_wall_ms_;
  last_cpu_ms_ = cpu;
  last_wall_ms_ = wall;
}

TrackingStage StageClock::switch_to(TrackingStage next) {
  const TrackingStage left = current_;
  if (next == current_) return left;
  charge();
  current_ = next;
  return left;
}

TrackingStageTimes StageClock::read() {
  charge();
  return times_;
}

}  // namespace edge_slam
