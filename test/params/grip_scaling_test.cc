// ScaleGrip / UnscaleGrip (params/schema/grip_scaling.h): a scenario's grip factors applied to a
// vehicle's grip and taken off again, member by member through GripParams::Visit.
#include "params/schema/grip_scaling.h"

#include <gtest/gtest.h>

#include <string>
#include <type_traits>
#include <vector>

namespace scw::params {
namespace {

std::vector<std::string> Keys() {
  std::vector<std::string> keys;
  const GripParams g;
  ForEachField(g, [&](const std::string& key, const auto&, const Meta&) { keys.push_back(key); });
  return keys;
}

/// Every member of `g` as a list of numbers, by key.
std::vector<std::vector<double>> Values(const GripParams& g) {
  std::vector<std::vector<double>> out;
  ForEachField(g, [&](const std::string&, const auto& member, const Meta&) {
    if constexpr (std::is_same_v<std::decay_t<decltype(member)>, double>)
      out.push_back({member});
    else
      out.push_back(member);
  });
  return out;
}

GripParams Vehicle() {
  GripParams g;
  g.mu = 0.9;
  g.front_mu_x = 1.1;
  g.front_mu_y = 0.95;
  g.rear_mu_x = 1.05;
  g.rear_mu_y = 0.85;
  g.wheel_mu_x = {1.0, 0.7, 1.2, 0.6};
  g.wheel_mu_y = {0.8, 1.0, 0.9, 1.3};
  return g;
}

TEST(GripScalingTest, ScalesEachMemberByTheFactorOfItsKeyOnly) {
  const std::vector<std::string> keys = Keys();
  ASSERT_EQ(keys.size(), 7u);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    GripParams factors;  // all 1
    ForEachField(factors, [&](const std::string& key, auto& member, const Meta&) {
      if (key != keys[k]) return;
      if constexpr (std::is_same_v<std::decay_t<decltype(member)>, double>)
        member = 0.5;
      else
        member = {0.5, 0.25, 2.0, 4.0};
    });
    GripParams g = Vehicle();
    ScaleGrip(factors, &g);
    const auto before = Values(Vehicle()), after = Values(g), f = Values(factors);
    for (std::size_t m = 0; m < after.size(); ++m)
      for (std::size_t i = 0; i < after[m].size(); ++i)
        EXPECT_EQ(after[m][i], before[m][i] * f[m][i]) << keys[m] << "[" << i << "]";
    EXPECT_NE(after[k], before[k]) << keys[k];
    UnscaleGrip(factors, &g);
    const auto back = Values(g);
    for (std::size_t m = 0; m < back.size(); ++m)
      for (std::size_t i = 0; i < back[m].size(); ++i)
        EXPECT_EQ(back[m][i], after[m][i] / f[m][i]) << keys[m] << "[" << i << "]";
    EXPECT_EQ(back, before) << keys[k];  // powers of two: exact
  }
}

TEST(GripScalingTest, UnscaleUndoesScaleUpToRounding) {
  GripParams factors;
  factors.mu = 0.7;
  factors.rear_mu_y = 0.8;
  factors.wheel_mu_x = {1.0, 0.55, 1.0, 0.55};
  GripParams g = Vehicle();
  ScaleGrip(factors, &g);
  EXPECT_NEAR(g.mu, 0.63, 1e-15);
  EXPECT_NEAR(g.rear_mu_y, 0.68, 1e-15);
  EXPECT_NEAR(g.wheel_mu_x[1], 0.385, 1e-15);
  UnscaleGrip(factors, &g);
  const auto back = Values(g), original = Values(Vehicle());
  for (std::size_t m = 0; m < back.size(); ++m)
    for (std::size_t i = 0; i < back[m].size(); ++i) EXPECT_NEAR(back[m][i], original[m][i], 1e-15);
}

}  // namespace
}  // namespace scw::params
