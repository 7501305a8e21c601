#include "controller/common/per_wheel_ops.h"

#include <gtest/gtest.h>

#include <limits>

namespace scw::controller {
namespace {

TEST(PerWheelOpsTest, ElementWise) {
  const Wheels a{1.0, -2.0, 3.0, -4.0};
  const Wheels b{0.5, 0.5, 0.5, 0.5};
  EXPECT_EQ(Add(a, b), (Wheels{1.5, -1.5, 3.5, -3.5}));
  EXPECT_EQ(Sub(a, b), (Wheels{0.5, -2.5, 2.5, -4.5}));
  EXPECT_EQ(Mul(a, b), (Wheels{0.5, -1.0, 1.5, -2.0}));
  EXPECT_EQ(Scale(a, 2.0), (Wheels{2.0, -4.0, 6.0, -8.0}));
  EXPECT_EQ(Min(a, b), (Wheels{0.5, -2.0, 0.5, -4.0}));
  EXPECT_EQ(Max(a, b), (Wheels{1.0, 0.5, 3.0, 0.5}));
  EXPECT_EQ(Clamp(a, -1.0, 1.0), (Wheels{1.0, -1.0, 1.0, -1.0}));
  EXPECT_EQ(MaxElement(a), 3.0);
  EXPECT_EQ(MinElement(a), -4.0);
  EXPECT_EQ(FromFrontRear(1.0, 2.0), (Wheels{1.0, 1.0, 2.0, 2.0}));
  EXPECT_EQ(FromLeftRight(1.0, 2.0), (Wheels{1.0, 2.0, 1.0, 2.0}));
  EXPECT_TRUE(AllFinite(a));
  EXPECT_FALSE(AllFinite(Wheels{0.0, 0.0, std::numeric_limits<double>::quiet_NaN(), 0.0}));
}

}  // namespace
}  // namespace scw::controller
