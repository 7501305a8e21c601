#include "controller/common/ring_buffer_mean.h"

#include <gtest/gtest.h>

namespace scw::controller {
namespace {

TEST(RingBufferMeanTest, ZerosCountUntilFilledAndOldestIsOverwritten) {
  RingBufferMean<8> buf;
  EXPECT_EQ(buf.Mean(4), 0.0);
  buf.Push(4.0, 4);
  EXPECT_DOUBLE_EQ(buf.Mean(4), 1.0);  // (4 + 0 + 0 + 0)/4
  buf.Push(4.0, 4);
  buf.Push(4.0, 4);
  buf.Push(4.0, 4);
  EXPECT_DOUBLE_EQ(buf.Mean(4), 4.0);
  buf.Push(0.0, 4);  // overwrites the first sample
  EXPECT_DOUBLE_EQ(buf.Mean(4), 3.0);
}

TEST(RingBufferMeanTest, LengthIsClampedToCapacity) {
  RingBufferMean<2> buf;
  buf.Push(2.0, 10);
  buf.Push(4.0, 10);
  buf.Push(6.0, 10);
  EXPECT_DOUBLE_EQ(buf.Mean(10), 5.0);
  RingBufferMean<2> one;
  one.Push(3.0, 0);
  EXPECT_DOUBLE_EQ(one.Mean(0), 3.0);
}

}  // namespace
}  // namespace scw::controller
