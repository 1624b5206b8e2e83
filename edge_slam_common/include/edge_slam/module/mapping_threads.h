// Local-Mapping and, when enabled, Loop-Closing on one map: built, wired (every KeyFrame
// Local-Mapping is done with goes on to Loop-Closing), started, waited for and stopped the same
// way for the monolithic system (SlamSystem) and the edge (EdgeSession).
// Usage: construct, set the owner's hooks on mapping() (they are read by its thread), start().
#pragma once
#include <memory>

#include "edge_slam/module/local_mapping.h"
#include "edge_slam/module/loop_closing.h"

namespace edge_slam {

class MappingThreads {
 public:
  MappingThreads(std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
                 std::shared_ptr<const BowVocabulary> vocabulary, const LocalMappingParams& mapping,
                 const LoopClosingParams& loop, bool loop_closing);
  ~MappingThreads();  // stop(false)
  MappingThreads(const MappingThreads&) = delete;
  MappingThreads& operator=(const MappingThreads&) = delete;

  void start();
  // Waits up to timeout_s (one deadline for all) until Local-Mapping has processed everything
  // queued and Loop-Closing (its full BA included) is quiet, `rounds` times over: a processed
  // KeyFrame goes on to Loop-Closing, whose correction pauses mapping, which may then queue
  // more. False when the deadline passed first. The threads keep running.
  bool wait_until_idle(double timeout_s, int rounds = 2) const;
  // Stops both threads: with drain, after what is queued; without, at once.
  void stop(bool drain);

  LocalMapping& mapping() { return *mapping_; }
  const LocalMapping& mapping() const { return *mapping_; }
  LoopClosing* loop() { return loop_.get(); }
  const LoopClosing* loop() const { return loop_.get(); }

 private:
  std::unique_ptr<LocalMapping> mapping_;
  std::unique_ptr<LoopClosing> loop_;  // null without loop closing
};

}  // namespace edge_slam
