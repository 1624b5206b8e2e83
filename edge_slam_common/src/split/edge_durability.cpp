#include "edge_slam/split/edge_durability.h"

#include <sys/stat.h>

#include <cstdio>
#include <random>
#include <stdexcept>

#include "edge_slam/module/edge_session.h"
#include "edge_slam/util/log.h"
#include "edge_slam/util/wall_clock.h"

namespace edge_slam {

uint64_t random_boot_id() {
  std::random_device rd;
  return (static_cast<uint64_t>(rd()) << 32) ^ rd() ^ static_cast<uint64_t>(wall_clock_seconds() * 1e6);
}

EdgeDurability::EdgeDurability(EdgeSession& session, DurabilityParams params, BootIds boot_ids)
    : session_(session), params_(std::move(params)), boot_ids_(std::move(boot_ids)) {
  boot_id_ = boot_ids_();
}

RestoreResult EdgeDurability::restore(double now) {
  const std::string& file = params_.checkpoint_file;
  if (!persistent()) return RestoreResult::kNoCheckpoint;
  struct stat st;
  if (::stat(file.c_str(), &st) != 0) {
    log_info("no checkpoint at " + file + " yet: starting with an empty Global-Map");
    return RestoreResult::kNoCheckpoint;
  }
  try {
    session_.load_map(file);
    all_durable_as_received();  // it came from the file: durable by definition
    std::string seqs;
    for (int r = 0; r < session_.robots(); ++r) seqs += (r ? ", " : "") + std::to_string(durable_seq_[r].load());
    log_info("restored the Global-Map from " + file + ": " + std::to_string(session_.global_map()->num_keyframes()) +
             " KeyFrames, KeyFrame seqs up to " + seqs + (session_.robots() > 1 ? " (per robot)" : ""));
    return RestoreResult::kRestored;
  } catch (const std::exception& e) {
    const std::string aside = file + ".corrupt-" + std::to_string(static_cast<long long>(now));
    const bool moved = std::rename(file.c_str(), aside.c_str()) == 0;
    log_error(std::string("cannot restore the checkpoint (") + e.what() + "): starting with an empty Global-Map; the file " +
              (moved ? "was renamed " + aside : std::string("could not be renamed and will be overwritten")));
    return moved ? RestoreResult::kCorruptRenamed : RestoreResult::kCorruptNotRenamed;
  }
}

bool EdgeDurability::checkpoint(const char* why, double now, std::string* error) {
  if (!persistent()) {
    if (error) *error = "no checkpoint file set";
    return false;
  }
  if (checkpointing_.exchange(true)) {
    if (error) *error = "a checkpoint is being written right now; try again";
    return false;
  }
  bool ok = true;
  try {
    const std::vector<uint64_t> durable = session_.save_map(params_.checkpoint_file);
    for (size_t r = 0; r < durable.size() && r < durable_seq_.size(); ++r)
      for (uint64_t seen = durable_seq_[r].load(); durable[r] > seen && !durable_seq_[r].compare_exchange_weak(seen, durable[r]);) {
      }
    ++checkpoints_;
    log_debug(std::string(why) + " checkpoint: robot 0's KeyFrame seqs up to " + std::to_string(durable.at(0)) + " durable");
  } catch (const std::exception& e) {
    ok = false;
    if (error) *error = e.what();
    if (failure_log_.allow(now)) log_error(std::string(why) + " checkpoint failed: " + e.what());
  }
  checkpointing_ = false;
  return ok;
}

bool EdgeDurability::save(const std::string& path, double now, std::string* error) {
  const std::string target = path.empty() ? params_.checkpoint_file : path;
  if (target.empty()) {
    if (error) *error = "no path given and no ~checkpoint_file set";
    return false;
  }
  if (target == params_.checkpoint_file) return checkpoint("requested", now, error);
  try {
    session_.save_map(target);
    return true;
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return false;
  }
}

void EdgeDurability::load(const std::string& path) {
  const std::string source = path.empty() ? params_.checkpoint_file : path;
  if (source.empty()) throw std::runtime_error("no path given and no ~checkpoint_file set");
  session_.load_map(source);
  if (source == params_.checkpoint_file)
    all_durable_as_received();
  else
    for (auto& seq : durable_seq_) seq = 0;
  boot_id_ = boot_ids_();
}

void EdgeDurability::all_durable_as_received() {
  for (int r = 0; r < static_cast<int>(durable_seq_.size()); ++r)
    durable_seq_[r] = r < session_.robots() ? session_.counters(r).received_seq : 0;
}

KeyFrameAck EdgeDurability::ack(int robot) {
  if (!valid_robot_index(robot)) return {};
  const EdgeCounters c = session_.counters(robot);
  KeyFrameAck a;
  a.boot_id = boot_id_;
  a.received_seq = c.received_seq;
  a.persistent = persistent();
  a.durable_seq = durable_seq_[robot];
  a.mapped_seq = c.mapped_seq;
  a.mapper_busy_elsewhere = c.mapper_busy_elsewhere;
  last_acked_mapped_seq_[robot] = a.mapped_seq;
  last_acked_busy_elsewhere_[robot] = a.mapper_busy_elsewhere;
  return a;
}

bool EdgeDurability::mapping_progressed(int robot) const {
  if (!valid_robot_index(robot)) return false;
  const EdgeCounters c = session_.counters(robot);
  return c.mapped_seq != last_acked_mapped_seq_[robot] || c.mapper_busy_elsewhere != last_acked_busy_elsewhere_[robot];
}

}  // namespace edge_slam
