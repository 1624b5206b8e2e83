// Per-stage CPU and wall time of one tracked frame (extract, match, pose, local-map search,
// KeyFrame creation), exclusive: time spent in a nested stage (a pose optimisation inside the
// motion-model step) counts for the nested stage only, so the stages add up to the frame.
// Tracking installs a StageClock for the current thread around each frame; the code of a stage
// opens a StageScope, which finds that clock through a thread-local pointer (a no-op when none
// is installed, e.g. a pose optimisation called from a test or from the edge). Cost: one
// thread-CPU clock read and one steady-clock read per stage switch (~1 us a frame).
#pragma once
#include <array>

namespace edge_slam {

enum class TrackingStage { kExtract = 0, kMatch, kPose, kLocalMap, kKeyFrame, kCount };
constexpr int kTrackingStages = static_cast<int>(TrackingStage::kCount);
const char* to_string(TrackingStage s);  // "extract", "match", "pose", "local_map", "keyframe"

struct TrackingStageTimes {
  std::array<double, kTrackingStages> cpu_ms{};   // CPU time of the tracking thread
  std::array<double, kTrackingStages> wall_ms{};
  double cpu(TrackingStage s) const { return cpu_ms[static_cast<int>(s)]; }
  double wall(TrackingStage s) const { return wall_ms[static_cast<int>(s)]; }
};

class StageClock {
 public:
  // Starts timing `initial` and makes this the thread's clock until destroyed (the previous
  // one, if any, is restored then: clocks nest).
  explicit StageClock(TrackingStage initial);
  ~StageClock();
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  // Charges the time since the last switch to the current stage; returns the stage left.
  TrackingStage switch_to(TrackingStage next);
  // The times so far, the running stage included.
  TrackingStageTimes read();

  static StageClock* active();  // the current thread's innermost clock, or null

 private:
  void charge();
  TrackingStageTimes times_;
  TrackingStage current_;
  double last_cpu_ms_, last_wall_ms_;
  StageClock* previous_;
};

// Runs the enclosing block as `stage` on the thread's clock (if any), then returns to the
// stage that was running.
class StageScope {
 public:
  explicit StageScope(TrackingStage stage)
      : clock_(StageClock::active()), previous_(clock_ ? clock_->switch_to(stage) : stage) {}
  ~StageScope() {
    if (clock_) clock_->switch_to(previous_);
  }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  StageClock* clock_;
  TrackingStage previous_;
};

}  // namespace edge_slam
