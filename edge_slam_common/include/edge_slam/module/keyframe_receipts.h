// Edge side of KeyFrame delivery (module/keyframe_delivery.h): which KeyFrame seqs arrived, as
// the highest seq up to which all did (what the edge acknowledges and checkpoints) plus the
// ones that came early. The mobile's floor (seqs it will never send again) closes gaps left by
// records its bound dropped. Not thread-safe: EdgeSession holds its lock around it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <set>

namespace edge_slam {

class KeyFrameReceipts {
 public:
  // Out-of-order seqs kept at most; beyond, the newest is forgotten: the mobile frees nothing
  // unacknowledged, so it is resent later (never lost).
  static constexpr size_t kMaxEarly = 10000;

  void mark(uint64_t seq);
  void skip_through(uint64_t floor);
  void restore(uint64_t contiguous);  // from a checkpoint: everything after is unknown
  uint64_t contiguous() const { return contiguous_; }

 private:
  void absorb();
  uint64_t contiguous_ = 0;
  std::set<uint64_t> early_;  // received seqs > contiguous_ + 1
};

}  // namespace edge_slam
