#include <gtest/gtest.h>

#include "simulator/plant/cycle_kind.hpp"

namespace lptn::plant {
namespace {

TEST(CycleKind, NamesRoundTrip) {
  for (const CycleKind kind : kAllCycleKinds) {
    const auto parsed = cycle_kind_from_string(to_string(kind));
    ASSERT_TRUE(parsed.has_value()) << to_string(kind);
    EXPECT_EQ(*parsed, kind);
  }
  EXPECT_EQ(to_string(CycleKind::intercity), "intercity");
}

TEST(CycleKind, UnknownNamesAreRejected) {
  EXPECT_FALSE(cycle_kind_from_string("").has_value());
  EXPECT_FALSE(cycle_kind_from_string("metro").has_value());
  EXPECT_FALSE(cycle_kind_from_string("Suburban").has_value());
  EXPECT_FALSE(cycle_kind_from_string("hilly ").has_value());
}

}  // namespace
}  // namespace lptn::plant
