// Subscribes to one of the split's topics with the input checks of both nodelets in one place:
// the bytes are decoded with the length-checked deserializer (checked_deserialization.h, so a
// corrupt array length never reaches roscpp's own, unchecked one), then turned into a record
// with the field checks (message_conversion.h). A message failing either goes to `malformed`
// with the reason and its size; a good one to `deliver` with its record and wire size.
#pragma once
#include <edge_slam_bridge/checked_deserialization.h>
#include <edge_slam_bridge/raw_message.h>
#include <edge_slam_bridge/wire_size.h>
#include <ros/ros.h>

#include <functional>
#include <string>

namespace edge_slam {

template <class Message, class Record>
ros::Subscriber subscribe_checked(ros::NodeHandle& nh, const std::string& topic, uint32_t queue_size,
                                  std::function<void(const Record& record, size_t bytes)> deliver,
                                  std::function<void(const std::string& why, size_t bytes)> malformed) {
  using Raw = RawMessage<Message>;
  const boost::function<void(const boost::shared_ptr<const Raw>&)> on_bytes =
      [deliver, malformed](const boost::shared_ptr<const Raw>& raw) {
        Message msg;
        DecodeStatus status = deserialize_checked(raw->bytes.data(), raw->bytes.size(), msg);
        if (!status.ok) return malformed(status.error, raw->bytes.size());
        const size_t bytes = wire_size(msg);
        Record record;
        status = from_message(msg, record);
        if (!status.ok) return malformed(status.error, bytes);
        deliver(record, bytes);
      };
  return nh.subscribe<Raw>(topic, queue_size, on_bytes);
}

}  // namespace edge_slam
