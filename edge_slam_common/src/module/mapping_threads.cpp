#include "edge_slam/module/mapping_threads.h"

#include <algorithm>
#include <chrono>

namespace edge_slam {

MappingThreads::MappingThreads(std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
                               std::shared_ptr<const BowVocabulary> vocabulary, const LocalMappingParams& mapping,
                               const LoopClosingParams& loop, bool loop_closing)
    : mapping_(std::make_unique<LocalMapping>(map, database, std::move(vocabulary), mapping)) {
  if (!loop_closing) return;
  loop_ = std::make_unique<LoopClosing>(std::move(map), std::move(database), mapping_.get(), loop);
  mapping_->on_keyframe_processed = [this](const std::shared_ptr<KeyFrame>& kf) { loop_->insert_keyframe(kf); };
}

MappingThreads::~MappingThreads() { stop(false); }

void MappingThreads::start() {
  if (loop_) loop_->start();
  mapping_->start();
}

bool MappingThreads::wait_until_idle(double timeout_s, int rounds) const {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  auto remaining = [&] { return std::max(0.0, std::chrono::duration<double>(deadline - Clock::now()).count()); };
  bool ok = true;
  for (int round = 0; round < rounds; ++round) {
    ok = mapping_->wait_until_idle(remaining()) && ok;
    if (loop_) ok = loop_->wait_until_idle(remaining()) && ok;
  }
  return ok;
}

void MappingThreads::stop(bool drain) {
  mapping_->shutdown(drain);
  if (loop_) loop_->shutdown(drain);
}

}  // namespace edge_slam
