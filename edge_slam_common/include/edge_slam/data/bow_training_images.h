// Which image files a vocabulary is trained on: an input is a TUM RGB-D sequence folder
// (has rgb.txt; frames in its order) or a plain folder of .png/.jpg/.jpeg images (sorted by name).
#pragma once
#include <string>
#include <vector>

namespace edge_slam {

// Throws std::runtime_error naming the input if it is missing, not a folder (a .bag gets a
// hint to use the ROS trainer), has a malformed rgb.txt, or holds no images.
std::vector<std::string> list_training_images(const std::string& input);

}  // namespace edge_slam
