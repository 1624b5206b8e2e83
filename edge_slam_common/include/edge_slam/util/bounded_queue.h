// A bounded multi-producer / multi-consumer queue: how threads hand work to each other
// (mobile KeyFrame sender, edge KeyFrame callback -> Local-Mapping -> Loop-Closing).
// push() never blocks its producer: when full, the oldest item is evicted and returned so
// the caller can count or re-route it (a producer such as tracking must never stall).
// close() wakes every waiter; pop() then drains what is left and returns nullopt at the end.
#pragma once
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace edge_slam {

template <class T>
class BoundedQueue {
 public:
  explicit BoundedQueue(size_t capacity) : capacity_(capacity) {
    if (capacity_ == 0) throw std::invalid_argument("BoundedQueue capacity must be >= 1");
  }

  // Returns the evicted oldest item when the queue was full; nullopt otherwise.
  // Pushing into a closed queue is refused: the item is handed back.
  std::optional<T> push(T item) {
    std::optional<T> evicted;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return std::optional<T>(std::move(item));
      if (items_.size() >= capacity_) {
        evicted.emplace(std::move(items_.front()));
        items_.pop_front();
        ++evictions_;
      }
      items_.push_back(std::move(item));
    }
    ready_.notify_one();
    return evicted;
  }

  // Blocks until an item arrives or the queue is closed and empty.
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return closed_ || !items_.empty(); });
    return take_locked();
  }

  // Like pop() but gives up after `timeout`.
  template <class Rep, class Period>
  std::optional<T> pop_for(std::chrono::duration<Rep, Period> timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait_for(lock, timeout, [&] { return closed_ || !items_.empty(); });
    return take_locked();
  }

  std::optional<T> try_pop() {
    std::lock_guard<std::mutex> lock(mutex_);
    return take_locked();
  }

  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    items_.clear();
  }

  size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }
  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }
  size_t capacity() const { return capacity_; }
  size_t evictions() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return evictions_;
  }

 private:
  std::optional<T> take_locked() {
    if (items_.empty()) return std::nullopt;
    std::optional<T> item(std::move(items_.front()));
    items_.pop_front();
    return item;
  }

  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<T> items_;
  bool closed_ = false;
  size_t evictions_ = 0;
};

}  // namespace edge_slam
