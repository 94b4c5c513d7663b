// Parameter names, layout and the normalized coordinates of calibrators.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "lptn/model.hpp"

namespace lptn {
namespace {

TEST(Params, NamesAreUniqueAndFindable) {
  std::set<std::string> names;
  for (int i = 0; i < kNumParams; ++i) {
    const ParamSpec& s = param_spec(i);
    EXPECT_TRUE(names.insert(std::string(s.name)).second) << s.name;
    EXPECT_EQ(param_index(s.name), i);
    EXPECT_LE(s.min, s.initial) << s.name;
    EXPECT_LE(s.initial, s.max) << s.name;
    EXPECT_FALSE(s.unit.empty()) << s.name;
  }
  EXPECT_EQ(param_index("no_such_parameter"), -1);
}

TEST(Params, EveryEffectParameterBelongsToItsEffect) {
  for (int i = 0; i < kNumPaperParams; ++i) EXPECT_EQ(effect_of_param(i), -1);
  int count = 0;
  for (int e = 0; e < kNumEffects; ++e) {
    for (int k = 0; k < EffectLibrary::kParamCounts[e]; ++k) {
      EXPECT_EQ(effect_of_param(kNumPaperParams + EffectLibrary::kParamOffsets[e] + k), e);
      ++count;
    }
  }
  EXPECT_EQ(count + kNumPaperParams, kNumParams);
  EXPECT_EQ(effect_index("airgap"), 0);
  // The named effects first, then the dictionary's terms as one group (effects/library.hpp).
  EXPECT_EQ(effect_index("sensor_lag"), 4);
  EXPECT_EQ(EffectLibrary::kKinds[4], EffectKind::library);
  EXPECT_EQ(EffectLibrary::kKinds[5], EffectKind::term);
  EXPECT_EQ(EffectLibrary::kKinds[kNumEffects - 1], EffectKind::term);
  EXPECT_EQ(effect_index("heat_stator_winding_i2f"), 5);
  EXPECT_EQ(EffectLibrary::kNodes[5], kStatorWinding);
  // Every name (built at compile time for the terms) is unique, so every lookup by name is unambiguous.
  for (int i = 0; i < kNumParams; ++i)
    for (int j = i + 1; j < kNumParams; ++j) EXPECT_NE(param_spec(i).name, param_spec(j).name);
  for (int i = 0; i < kNumEffects; ++i)
    for (int j = i + 1; j < kNumEffects; ++j) EXPECT_NE(EffectLibrary::kNames[i], EffectLibrary::kNames[j]);
  EXPECT_EQ(effect_index("flux_capacitor"), -1);
}

TEST(Params, LogScaleMapsBoundsToPlusMinusOneAndMidpointToGeometricMean) {
  EXPECT_NEAR(to_normalized(1.0, 1.0, 1000.0), -1.0, 1e-12);
  EXPECT_NEAR(to_normalized(1000.0, 1.0, 1000.0), 1.0, 1e-12);
  EXPECT_NEAR(from_normalized(0.0, 1.0, 1000.0), std::sqrt(1000.0), 1e-9);
  for (double v : {1.0, 3.7, 40.0, 999.0}) EXPECT_NEAR(from_normalized(to_normalized(v, 1.0, 1000.0), 1.0, 1000.0), v, 1e-9 * v);
}

TEST(Params, FractionsStartingAtZeroUseALinearScale) {
  EXPECT_FALSE(uses_log_scale(0.0, 1.0));
  EXPECT_NEAR(from_normalized(0.0, 0.0, 1.0), 0.5, 1e-15);
  EXPECT_NEAR(to_normalized(0.25, 0.0, 1.0), -0.5, 1e-15);
}

}  // namespace
}  // namespace lptn
