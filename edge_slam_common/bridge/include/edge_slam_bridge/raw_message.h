// A subscription type that keeps a message's serialized bytes: RawMessage<M> negotiates with
// publishers exactly as M does (same type name and MD5), but roscpp only copies the bytes, so
// the receiver decodes them with deserialize_checked() (array lengths checked against the
// buffer before anything is allocated) instead of letting roscpp trust a corrupt length field.
#pragma once
#include <ros/message_traits.h>
#include <ros/serialization.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace edge_slam {

template <class M>
struct RawMessage {
  std::vector<uint8_t> bytes;
};

}  // namespace edge_slam

namespace ros {
namespace message_traits {

template <class M>
struct MD5Sum<edge_slam::RawMessage<M>> {
  static const char* value() { return MD5Sum<M>::value(); }
  static const char* value(const edge_slam::RawMessage<M>&) { return value(); }
};
template <class M>
struct DataType<edge_slam::RawMessage<M>> {
  static const char* value() { return DataType<M>::value(); }
  static const char* value(const edge_slam::RawMessage<M>&) { return value(); }
};
template <class M>
struct Definition<edge_slam::RawMessage<M>> {
  static const char* value() { return Definition<M>::value(); }
  static const char* value(const edge_slam::RawMessage<M>&) { return value(); }
};

}  // namespace message_traits

namespace serialization {

template <class M>
struct Serializer<edge_slam::RawMessage<M>> {
  template <typename Stream>
  inline static void write(Stream& stream, const edge_slam::RawMessage<M>& m) {
    if (!m.bytes.empty()) std::memcpy(stream.advance(static_cast<uint32_t>(m.bytes.size())), m.bytes.data(), m.bytes.size());
  }
  template <typename Stream>
  inline static void read(Stream& stream, edge_slam::RawMessage<M>& m) {
    const uint32_t n = stream.getLength();  // the whole message: what is left of the stream
    m.bytes.assign(stream.getData(), stream.getData() + n);
    stream.advance(n);
  }
  inline static uint32_t serializedLength(const edge_slam::RawMessage<M>& m) {
    return static_cast<uint32_t>(m.bytes.size());
  }
};

}  // namespace serialization
}  // namespace ros
