#include <gtest/gtest.h>

#include "ldoem/endpoints/output_queue.hpp"

namespace ldoem::endpoints {
namespace {

TEST(OutputQueue, PartialSends_ResumeWhereTheyStopped) {
  OutputQueue queue(100);
  ASSERT_TRUE(queue.push(protocol::Bytes{1, 2, 3}));
  ASSERT_TRUE(queue.push(protocol::Bytes{4, 5}));
  EXPECT_EQ(queue.size_bytes(), 5u);
  queue.consume(2);
  ASSERT_EQ(queue.front().size(), 1u);
  EXPECT_EQ(queue.front()[0], 3);
  queue.consume(1);
  EXPECT_EQ(queue.front()[0], 4);
  queue.consume(2);
  EXPECT_TRUE(queue.empty());
}

TEST(OutputQueue, OverTheBound_RefusedAndUnchanged) {
  OutputQueue queue(4);
  ASSERT_TRUE(queue.push(protocol::Bytes{1, 2, 3}));
  EXPECT_FALSE(queue.push(protocol::Bytes{4, 5}));
  EXPECT_EQ(queue.size_bytes(), 3u);
  EXPECT_TRUE(queue.push(protocol::Bytes{4}));
}

}  // namespace
}  // namespace ldoem::endpoints
