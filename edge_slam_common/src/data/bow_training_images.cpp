// Listing the frames of a training input (TUM folder or image folder).
#include "edge_slam/data/bow_training_images.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace edge_slam {
namespace {

namespace fs = std::filesystem;

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Frames listed in a TUM rgb.txt ("timestamp path" lines, '#' comments), relative to its folder.
std::vector<std::string> tum_frames(const fs::path& folder) {
  const fs::path list = folder / "rgb.txt";
  std::ifstream in(list);
  if (!in) throw std::runtime_error("cannot read " + list.string());
  std::vector<std::string> frames;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string timestamp, file;
    if (!(fields >> timestamp >> file))
      throw std::runtime_error(list.string() + ": line " + std::to_string(number) + ": expected 'timestamp path'");
    frames.push_back((folder / file).string());
  }
  return frames;
}

std::vector<std::string> folder_images(const fs::path& folder) {
  std::vector<std::string> frames;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string extension = lowercase(entry.path().extension().string());
    if (entry.is_regular_file() && (extension == ".png" || extension == ".jpg" || extension == ".jpeg"))
      frames.push_back(entry.path().string());
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

}  // namespace

std::vector<std::string> list_training_images(const std::string& input) {
  const fs::path path(input);
  if (!fs::exists(path)) throw std::runtime_error("input '" + input + "' does not exist");
  if (lowercase(path.extension().string()) == ".bag")
    throw std::runtime_error("input '" + input + "' is a ROS bag: use train_vocabulary_bag (catkin build)");
  if (!fs::is_directory(path))
    throw std::runtime_error("input '" + input + "' is not a folder (expected an image folder or a TUM sequence)");
  std::vector<std::string> frames = fs::exists(path / "rgb.txt") ? tum_frames(path) : folder_images(path);
  if (frames.empty()) throw std::runtime_error("input '" + input + "' contains no .png/.jpg/.jpeg images");
  return frames;
}

}  // namespace edge_slam
