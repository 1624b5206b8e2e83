#include "edge_slam/module/keyframe_receipts.h"

#include <iterator>

namespace edge_slam {

void KeyFrameReceipts::mark(uint64_t seq) {
  if (seq <= contiguous_) return;  // a duplicate
  early_.insert(seq);
  if (early_.size() > kMaxEarly) early_.erase(std::prev(early_.end()));  // forget the newest: resent later
  absorb();
}

void KeyFrameReceipts::skip_through(uint64_t floor) {
  if (floor <= contiguous_) return;
  contiguous_ = floor;
  absorb();
}

void KeyFrameReceipts::restore(uint64_t contiguous) {
  contiguous_ = contiguous;
  early_.clear();
}

void KeyFrameReceipts::absorb() {
  while (!early_.empty() && *early_.begin() <= contiguous_ + 1) {
    if (*early_.begin() == contiguous_ + 1) ++contiguous_;
    early_.erase(early_.begin());
  }
}

}  // namespace edge_slam
