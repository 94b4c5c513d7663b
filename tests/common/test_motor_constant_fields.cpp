// The field list (lptn/motor_constant_fields.hpp) against MotorConstants itself: every member is
// in it, each entry fits its member, and cast() carries every one.
#include <gtest/gtest.h>

#include <cstddef>
#include <set>
#include <string>
#include <type_traits>
#include <utility>

#include "lptn_testing/distinct_motor_constants.hpp"
#include "lptn/motor_constants.hpp"

namespace lptn {
namespace {

// How many initializers T's aggregate initialization takes: one per member, one per element of an
// array member (brace elision), one for a base class. The compiler's count of the members, which
// a member added without its field-list entry changes.
struct AnyValue {
  template <class T>
  operator T() const;
};
template <std::size_t>
using AnyValueAt = AnyValue;

template <class T, std::size_t... I>
constexpr bool initializable_with(std::index_sequence<I...>) {
  return requires { T{AnyValueAt<I>{}...}; };
}

template <class T, std::size_t N = 0>
constexpr std::size_t initializer_count() {
  if constexpr (N > 200 || !initializable_with<T>(std::make_index_sequence<N + 1>{})) {
    return N;
  } else {
    return initializer_count<T, N + 1>();
  }
}

// The same count from a field list: each array's elements, one for anything else.
template <class Visit>
std::size_t listed_initializers(Visit visit) {
  std::size_t n = 0;
  visit([&](const MotorField&, const auto& member) {
    using M = std::remove_cvref_t<decltype(member)>;
    n += std::is_array_v<M> ? std::extent_v<M> : 1;
  });
  return n;
}

TEST(MotorConstantFields, TheNameplateListHasEveryMember) {
  const Nameplate<double> n;
  const std::size_t listed = listed_initializers([&](auto f) { for_each_nameplate_field(f, n); });
  EXPECT_EQ(initializer_count<Nameplate<double>>(), listed)
      << "a member of Nameplate is missing from for_each_nameplate_field (lptn/nameplate.hpp)";
}

TEST(MotorConstantFields, TheListHasEveryMember) {
  const MotorConstants<double> c;
  const Nameplate<double>& n = c;
  const std::size_t all = listed_initializers([&](auto f) { for_each_motor_constant(f, c); });
  const std::size_t nameplate = listed_initializers([&](auto f) { for_each_nameplate_field(f, n); });
  // The nameplate is MotorConstants' base: one initializer.
  EXPECT_EQ(initializer_count<MotorConstants<double>>(), all - nameplate + 1)
      << "a member of MotorConstants is missing from for_each_motor_constant (lptn/motor_constant_fields.hpp)";
  EXPECT_EQ(initializer_count<MotorConstants<float>>(), all - nameplate + 1);
}

TEST(MotorConstantFields, EachEntryFitsItsMember) {
  MotorConstants<double> c;
  std::set<std::string> keys;
  std::set<std::string> sections;
  std::string section;
  int columns_expected = 0;
  for_each_motor_constant(
      [&](const MotorField& f, const auto& member) {
        using M = std::remove_cvref_t<decltype(member)>;
        const std::string name(f.name);
        switch (f.shape) {
          case FieldShape::integer:
          case FieldShape::table_size:
            EXPECT_TRUE((std::is_same_v<M, int>)) << name;
            EXPECT_GT(f.max_count, 0) << name;
            break;
          case FieldShape::scalar: EXPECT_TRUE((std::is_same_v<M, double>)) << name; break;
          case FieldShape::table_column:
            EXPECT_TRUE((std::is_same_v<M, double[kMaxHarmonicPoints]>)) << name;
            EXPECT_GT(columns_expected, 0) << name << ": a column with no table_size before it";
            --columns_expected;
            break;
          case FieldShape::per_node:
            EXPECT_TRUE((std::is_same_v<M, double[kNumNodes]>)) << name;
            for (std::string_view key : f.node_keys) EXPECT_TRUE(keys.insert(std::string(key)).second) << key;
            for (std::string_view node : f.node_names) EXPECT_FALSE(node.empty()) << name;
            break;
        }
        if (f.shape != FieldShape::table_column) {
          EXPECT_EQ(columns_expected, 0) << name << ": the table before it has fewer columns than it says";
        }
        if (f.shape == FieldShape::table_size) columns_expected = f.columns;
        if (f.shape != FieldShape::per_node && f.shape != FieldShape::table_size) {
          EXPECT_TRUE(keys.insert(name).second) << name << " twice";
        }
        // The reader and the writer take a section at a time: each one's fields come together.
        if (f.section != section) {
          section = std::string(f.section);
          EXPECT_TRUE(sections.insert(section).second) << name << ": section " << section << " again, apart";
        }
        // A value that must stay below another is read after it.
        if (!f.below.empty()) {
          EXPECT_EQ(keys.count(std::string(f.below.substr(f.below.find('.') + 1))), 1u) << name;
        }
        EXPECT_TRUE(f.note.empty() == (f.note_gap == 0)) << name;
      },
      c);
  EXPECT_EQ(columns_expected, 0);
}

TEST(MotorConstantFields, CastCarriesEveryMember) {
  const MotorConstants<double> d = testing::distinct_motor_constants();
  const MotorConstants<float> f = d.cast<float>();
  int compared = 0;
  for_each_motor_constant(
      [&](const MotorField& field, const auto& to, const auto& from) {
        using M = std::remove_cvref_t<decltype(to)>;
        if constexpr (std::is_array_v<M>) {
          for (std::size_t i = 0; i < std::extent_v<M>; ++i) EXPECT_EQ(to[i], static_cast<float>(from[i])) << field.name << i;
        } else {
          EXPECT_EQ(to, static_cast<M>(from)) << field.name;
        }
        ++compared;
      },
      f, d);
  EXPECT_GT(compared, 20);
  EXPECT_EQ(d.cast<double>().rated_current_a, d.rated_current_a);
}

}  // namespace
}  // namespace lptn
