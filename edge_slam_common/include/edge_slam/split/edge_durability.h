// The edge's side of KeyFrame durability (README "Delivery and persistence"): its boot id, the
// seq up to which received KeyFrames are in its last checkpoint, and the checkpoint file.
// - checkpoint(): the session snapshots under its locks and writes outside them (atomically);
//   one writer at a time (timer, service, shutdown), a second one is told to try again.
// - restore(): at start, a checkpoint that exists is loaded, and everything in it is durable.
//   A corrupt or unreadable one is renamed <file>.corrupt-<now> (kept for inspection, never
//   overwritten) and the edge starts empty; one clear error says so.
// - load(): a map loaded on request is a new session for the mobile: a new boot id, so it
//   resends all it holds beyond what the map says was received; durable only if it was the
//   checkpoint itself.
// - ack(): what the edge acknowledges (module/keyframe_delivery.h), with the mapped seq the
//   mobile's condition 2 reads; mapping_progressed() says when that changed since the last ack.
// Time and boot ids are arguments/injected, so the gtests need neither a clock nor a filesystem race.
// Thread-safe.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "edge_slam/module/keyframe_delivery.h"
#include "edge_slam/util/log_throttle.h"
#include "edge_slam/util/robot_ids.h"

namespace edge_slam {

class EdgeSession;

struct DurabilityParams {
  std::string checkpoint_file;   // empty: no persistence (the mobile frees a record once received)
  double checkpoint_period = 5;  // seconds between periodic checkpoints (load_checkpoint_period)
};

// A boot id that differs between two starts of the edge (random, mixed with the time).
uint64_t random_boot_id();

enum class RestoreResult { kNoCheckpoint, kRestored, kCorruptRenamed, kCorruptNotRenamed };

class EdgeDurability {
 public:
  using BootIds = std::function<uint64_t()>;
  EdgeDurability(EdgeSession& session, DurabilityParams params, BootIds boot_ids = random_boot_id);

  bool persistent() const { return !params_.checkpoint_file.empty(); }
  const DurabilityParams& params() const { return params_; }

  RestoreResult restore(double now);
  // False (with the reason in *error) when it failed or another checkpoint was being written.
  // Failures are logged at most every 30 s (`now`: seconds, any clock).
  bool checkpoint(const char* why, double now, std::string* error = nullptr);
  // ~save_map: the checkpoint when `path` is empty or the checkpoint file, else a copy there.
  bool save(const std::string& path, double now, std::string* error);
  // ~load_map (empty path = the checkpoint file); throws std::runtime_error with the reason.
  void load(const std::string& path);

  // Per robot (one edge, several mobiles: each has its own seqs; the boot id is the edge's).
  KeyFrameAck ack(int robot = 0);
  bool mapping_progressed(int robot = 0) const;

  uint64_t boot_id() const { return boot_id_; }
  // Robot `robot`'s KeyFrame seqs up to this one are in the last checkpoint.
  uint64_t durable_seq(int robot = 0) const { return valid_robot_index(robot) ? durable_seq_[robot].load() : 0; }
  uint64_t checkpoints() const { return checkpoints_; }

 private:
  EdgeSession& session_;
  DurabilityParams params_;
  BootIds boot_ids_;
  std::atomic<uint64_t> boot_id_{0}, checkpoints_{0};
  std::array<std::atomic<uint64_t>, kMaxRobots> durable_seq_{};  // per robot
  void all_durable_as_received();  // the session's state came from the checkpoint file
  std::array<std::atomic<uint64_t>, kMaxRobots> last_acked_mapped_seq_{};
  std::array<std::atomic<bool>, kMaxRobots> last_acked_busy_elsewhere_{};
  std::atomic<bool> checkpointing_{false};
  LogThrottle failure_log_{30.0};
};

}  // namespace edge_slam
