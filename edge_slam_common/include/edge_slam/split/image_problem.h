// Why the mobile dropped a camera frame before tracking it (the checks are the nodelet's,
// which sees the ROS images; the counts are the core's figures).
#pragma once

namespace edge_slam {

enum class ImageProblem { kNone, kStamp, kEncoding, kSize, kDepth };
inline constexpr int kImageProblemKinds = 5;

}  // namespace edge_slam
