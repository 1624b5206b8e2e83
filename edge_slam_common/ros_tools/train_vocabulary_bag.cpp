// Trains a bag-of-words vocabulary from the colour (or gray) image topic of ROS bags.
//   train_vocabulary_bag --out vocab.bin [--topic /camera/rgb/image_color] [--k 10] [--levels 6]
//                        [--every N] [--max-images M] [--seed S] <bags...>
// Reads sensor_msgs/Image (any cv_bridge-convertible encoding) or sensor_msgs/CompressedImage;
// uses the same ORB features and trainer as train_vocabulary. An --out path ending in .txt
// writes ORB-SLAM2's ORBvoc.txt format.
#include <cv_bridge/cv_bridge.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <opencv2/imgcodecs.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "edge_slam/data/bow_training_features.h"
#include "edge_slam/data/bow_training_options.h"

using namespace edge_slam;
using Clock = std::chrono::steady_clock;

namespace {

struct Options : TrainingOptions {
  std::string topic = "/camera/rgb/image_color";  // TUM RGB-D bags
  std::vector<std::string> bags;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// An empty message is --help.
[[noreturn]] void usage(const std::string& message) {
  exit_with_training_usage(
      "usage: train_vocabulary_bag --out vocab.bin [--topic /camera/rgb/image_color] [--k 10]\n"
      "                            [--levels 6] [--every N] [--max-images M] [--seed S] <bags...>\n",
      message);
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") usage("");
    if (arg.rfind("--", 0) != 0) {
      o.bags.push_back(arg);
      continue;
    }
    if (i + 1 >= argc) usage(arg + " needs a value");
    const char* value = argv[++i];
    if (arg == "--topic") {
      o.topic = value;
      continue;
    }
    try {
      if (!parse_training_flag(arg, value, o)) usage("unknown option " + arg);
    } catch (const std::invalid_argument& e) {
      usage(e.what());
    }
  }
  if (o.out.empty()) usage("--out is required");
  if (o.bags.empty()) usage("no bags given");
  return o;
}

cv::Mat gray_of(const rosbag::MessageInstance& message) {
  if (const auto image = message.instantiate<sensor_msgs::Image>())
    return cv_bridge::toCvCopy(image, "mono8")->image;
  if (const auto compressed = message.instantiate<sensor_msgs::CompressedImage>())
    return cv::imdecode(compressed->data, cv::IMREAD_GRAYSCALE);
  throw std::runtime_error("topic " + message.getTopic() + " carries " + message.getDataType() +
                           ", expected sensor_msgs/Image or sensor_msgs/CompressedImage");
}

std::string image_topics(const rosbag::Bag& bag) {
  rosbag::View all(bag);
  std::set<std::string> topics;
  for (const rosbag::ConnectionInfo* c : all.getConnections())
    if (c->datatype == "sensor_msgs/Image" || c->datatype == "sensor_msgs/CompressedImage") topics.insert(c->topic);
  std::string list;
  for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
  return list.empty() ? "none" : list;
}

// Appends the descriptors of every `every`-th image of the topic, up to `limit` images in total.
void read_bag(const std::string& path, const Options& o, std::vector<cv::Mat>& descriptors) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error("cannot open bag '" + path + "': " + e.what());
  }
  rosbag::View view(bag, rosbag::TopicQuery(o.topic));
  if (view.size() == 0)
    throw std::runtime_error("bag '" + path + "' has no messages on " + o.topic +
                             " (image topics in it: " + image_topics(bag) + "); choose one with --topic");
  long index = 0, used = 0;
  for (const rosbag::MessageInstance& message : view) {
    if (o.max_images >= 0 && static_cast<long>(descriptors.size()) >= o.max_images) break;
    if (index++ % o.every != 0) continue;
    const cv::Mat gray = gray_of(message);
    if (gray.empty()) throw std::runtime_error("bag '" + path + "': cannot decode image " + std::to_string(index));
    descriptors.push_back(extract_training_descriptors(gray));
    ++used;
  }
  std::printf("%s: %ld images on %s, using %ld\n", path.c_str(), static_cast<long>(view.size()), o.topic.c_str(), used);
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse_options(argc, argv);
  try {
    const auto start = Clock::now();
    std::vector<cv::Mat> descriptors;
    for (const std::string& bag : options.bags) read_bag(bag, options, descriptors);
    size_t total = 0;
    for (const cv::Mat& d : descriptors) total += static_cast<size_t>(d.rows);
    std::printf("extracted %zu descriptors from %zu images in %.1f s\n", total, descriptors.size(),
                seconds_since(start));

    train_and_save_vocabulary(descriptors, options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
