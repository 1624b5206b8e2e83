#include "edge_slam/module/slam_config.h"

#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/keyframe_delivery.h"
#include "edge_slam/module/local_mapping_params.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/tracking_params.h"

namespace edge_slam {

RunnerSettings load_runner_settings(const ConfigMap& cfg) {
  RunnerSettings s;
  s.vocabulary_path = cfg.get_string("vocabulary/path", "");
  s.final_full_ba_iterations = cfg.get_int_or("loop_closing/final_full_ba_iterations", 0, 0, 1000);
  return s;
}

void check_slam_config(const ConfigMap& slam) {
  load_orb_params(slam);
  load_tracking_params(slam);
  load_local_mapping_params(slam);
  load_runner_settings(slam);
  load_mobile_session_params(slam);
  load_edge_session_params(slam);
  load_delivery_params(slam);
  load_checkpoint_period(slam);
  warn_unknown_keys(slam);
}

}  // namespace edge_slam
