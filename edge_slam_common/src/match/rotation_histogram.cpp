#include "edge_slam/match/rotation_histogram.h"

#include <cmath>

namespace edge_slam {

void RotationHistogram::add(float angle_a, float angle_b, int match_index) {
  float rot = angle_a - angle_b;
  rot = std::fmod(rot, 360.f);
  if (rot < 0) rot += 360.f;
  int bin = static_cast<int>(std::lround(rot * kBins / 360.f));
  if (bin >= kBins) bin = 0;
  bins_[bin].push_back(match_index);
}

std::vector<int> RotationHistogram::inconsistent() const {
  int top[3] = {-1, -1, -1};
  auto count = [&](int b) { return b < 0 ? -1 : static_cast<int>(bins_[b].size()); };
  for (int b = 0; b < kBins; ++b) {
    const int n = count(b);
    if (n > count(top[0])) {
      top[2] = top[1];
      top[1] = top[0];
      top[0] = b;
    } else if (n > count(top[1])) {
      top[2] = top[1];
      top[1] = b;
    } else if (n > count(top[2])) {
      top[2] = b;
    }
  }
  const int max_n = count(top[0]);
  bool keep[kBins] = {};
  for (int t = 0; t < 3; ++t)
    if (top[t] >= 0 && count(top[t]) > 0 && (t == 0 || count(top[t]) >= 0.1 * max_n)) keep[top[t]] = true;
  std::vector<int> out;
  for (int b = 0; b < kBins; ++b)
    if (!keep[b]) out.insert(out.end(), bins_[b].begin(), bins_[b].end());
  return out;
}

}  // namespace edge_slam
