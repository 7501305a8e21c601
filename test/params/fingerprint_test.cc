// A schema struct's fingerprint: equal values give equal texts, and a change of any one field,
// nested or in a list, gives another.
#include "params/schema/fingerprint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "params/schema/field.h"
#include "params/schema/scenario_params.h"
#include "params/schema/vehicle_params.h"

namespace scw::params {
namespace {

TEST(Fingerprint, EqualValuesEqualTextsAnyChangedFieldAnotherText) {
  const VehicleParams a;
  EXPECT_EQ(Fingerprint(a), Fingerprint(VehicleParams{}));
  // Every field of the vehicle, one at a time (numbers nudged by one ulp-scale step, flags
  // flipped, texts extended, lists grown).
  const std::string base = Fingerprint(a);
  int fields = 0;
  ForEachField(a, [&](const std::string& path, const auto& member, const Meta&) {
    using T = std::remove_cvref_t<decltype(member)>;
    VehicleParams b = a;
    bool changed = false;
    ForEachField(b, [&](const std::string& p, auto& m, const Meta&) {
      using U = std::remove_cvref_t<decltype(m)>;
      if constexpr (std::is_same_v<U, T>) {
        if (p != path) return;
        if constexpr (std::is_same_v<U, double>) {
          m = std::nextafter(m, 1e300);
        } else if constexpr (std::is_same_v<U, bool>) {
          m = !m;
        } else if constexpr (std::is_same_v<U, std::string>) {
          m += "x";
        } else if constexpr (std::is_integral_v<U>) {
          m += 1;
        } else if constexpr (std::is_same_v<U, std::vector<double>>) {
          m.push_back(0.0);
        } else {
          return;
        }
        changed = true;
      }
    });
    if (!changed) return;
    ++fields;
    EXPECT_NE(Fingerprint(b), base) << path;
  });
  EXPECT_GT(fields, 100);
}

TEST(Fingerprint, ListLengthsAndTextBoundariesCount) {
  ScenarioParams a;
  const std::string base = Fingerprint(a);
  ScenarioParams b = a;
  b.events.late_braking.s.push_back(0.0);
  EXPECT_NE(Fingerprint(b), base);
  // A text is length-prefixed: moving a character between neighbours changes the text.
  ScenarioParams c = a, d = a;
  c.name = "ab";
  c.track = "c";
  d.name = "a";
  d.track = "bc";
  EXPECT_NE(Fingerprint(c), Fingerprint(d));
  EXPECT_EQ(Fingerprint(a, "x").rfind("x.", 0), 0u);
}

}  // namespace
}  // namespace scw::params
