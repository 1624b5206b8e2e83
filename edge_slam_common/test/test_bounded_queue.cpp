// The inter-thread queue: order, eviction of the oldest when full, close semantics, threads.
#include <edge_slam/util/bounded_queue.h>
#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace edge_slam {
namespace {

TEST(BoundedQueue, FifoAndEvictsOldestWhenFull) {
  BoundedQueue<int> q(3);
  EXPECT_FALSE(q.push(1));
  EXPECT_FALSE(q.push(2));
  EXPECT_FALSE(q.push(3));
  const std::optional<int> evicted = q.push(4);
  ASSERT_TRUE(evicted);
  EXPECT_EQ(*evicted, 1);
  EXPECT_EQ(q.evictions(), 1u);
  EXPECT_EQ(*q.try_pop(), 2);
  EXPECT_EQ(*q.try_pop(), 3);
  EXPECT_EQ(*q.try_pop(), 4);
  EXPECT_FALSE(q.try_pop());
}

TEST(BoundedQueue, CloseDrainsThenEnds) {
  BoundedQueue<int> q(4);
  q.push(7);
  q.close();
  const std::optional<int> refused = q.push(8);
  ASSERT_TRUE(refused);
  EXPECT_EQ(*refused, 8);
  EXPECT_EQ(*q.pop(), 7);
  EXPECT_FALSE(q.pop());
  EXPECT_FALSE(q.pop_for(std::chrono::milliseconds(1)));
  EXPECT_THROW(BoundedQueue<int>(0), std::invalid_argument);
}

TEST(BoundedQueue, ProducersAndConsumerLoseNothingBelowCapacity) {
  BoundedQueue<int> q(100000);
  std::vector<std::thread> producers;
  for (int p = 0; p < 4; ++p)
    producers.emplace_back([&q, p] {
      for (int i = 0; i < 1000; ++i) q.push(p * 1000 + i);
    });
  long sum = 0;
  int count = 0;
  std::thread consumer([&] {
    while (std::optional<int> v = q.pop()) {
      sum += *v;
      ++count;
    }
  });
  for (std::thread& t : producers) t.join();
  q.close();
  consumer.join();
  EXPECT_EQ(count, 4000);
  EXPECT_EQ(sum, 4000L * 3999 / 2);
}

TEST(BoundedQueue, CloseWakesBlockedConsumer) {
  BoundedQueue<int> q(2);
  std::thread consumer([&] { EXPECT_FALSE(q.pop()); });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  q.close();
  consumer.join();
}

}  // namespace
}  // namespace edge_slam
