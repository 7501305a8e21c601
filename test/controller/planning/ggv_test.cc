// The g-g-v table's description of its columns (GgvTable::Visit) and what derives from it.
#include "controller/planning/ggv.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test/common/field_count.h"

namespace scw::controller::planning {
namespace {

std::vector<std::string> Keys(const GgvTable& g) {
  std::vector<std::string> keys;
  params::ForEachField(g, [&](const std::string& key, const std::vector<double>&,
                              const params::Meta&) { keys.push_back(key); });
  return keys;
}

TEST(GgvTableTest, VisitListsEveryColumnOnceInCacheOrder) {
  EXPECT_EQ(Keys(GgvTable{}).size(), test::FieldCount<GgvTable>());
  // The preparation cache stores the columns in this order (tuning/sim/scenario.cc).
  EXPECT_EQ(Keys(GgvTable{}),
            (std::vector<std::string>{"speed", "ay_max", "ax_drive_max", "ax_brake_max",
                                      "drive_exponent", "brake_exponent"}));
  GgvTable g;
  std::vector<const std::vector<double>*> members;
  params::ForEachField(g, [&](const std::string&, std::vector<double>& column,
                              const params::Meta&) { members.push_back(&column); });
  EXPECT_EQ(members, (std::vector<const std::vector<double>*>{&g.speed, &g.ay_max, &g.ax_drive_max,
                                                              &g.ax_brake_max, &g.drive_exponent,
                                                              &g.brake_exponent}));
}

TEST(GgvTableTest, EmptyEmptiesEveryColumn) {
  const GgvTable e = GgvTable::Empty();
  params::ForEachField(e, [](const std::string& key, const std::vector<double>& column,
                             const params::Meta&) { EXPECT_TRUE(column.empty()) << key; });
  EXPECT_FALSE(e == GgvTable{});
}

TEST(GgvTableTest, EqualityComparesEveryColumn) {
  const GgvTable base = GgvTable::Constant(20.0, 8.0, 15.0, 1.6);
  EXPECT_TRUE(base == GgvTable::Constant(20.0, 8.0, 15.0, 1.6));
  for (const std::string& changed : Keys(base)) {
    GgvTable g = base;
    params::ForEachField(
        g, [&](const std::string& key, std::vector<double>& column, const params::Meta&) {
          if (key == changed) column.front() += 1.0;
        });
    EXPECT_FALSE(g == base) << changed;
  }
}

}  // namespace
}  // namespace scw::controller::planning
