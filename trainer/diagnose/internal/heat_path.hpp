// Which parameters share a heat path with an effect: a parameter correlated with the effect's but
// with no heat path to it (the paper leaves stator and rotor unconnected) is not confounded with
// it; the correlation is the fit's ill-conditioning, not physics. The effects' sides are their own
// (kSides, common/lptn/effects/effect.hpp).
#pragma once

#include "lptn/model.hpp"

namespace lptn::diagnose::internal {

inline unsigned side_bits(HeatSides s) { return static_cast<unsigned>(s); }

// The sides a parameter's heat flows through: a paper parameter's by what it scales (the loss
// shares split a loss between the sides), an effect's by its kSides.
inline HeatSides sides_of_param(int i) {
  switch (i) {
    case kLambda1s: case kLambda2s: case kLambda12s: case kKStemp: return HeatSides::stator;
    case kLambda1r: case kLambda2r: case kLambda12r: case kKRtemp: return HeatSides::rotor;
    default: break;
  }
  const int effect = effect_of_param(i);
  return effect < 0 ? HeatSides::both : EffectLibrary::kSides[static_cast<std::size_t>(effect)];
}

// Whether parameter `i` shares a heat path with `effect` in a model with `effects` enabled: once an
// enabled effect links the sides, every parameter does.
inline bool shares_heat_path(int i, int effect, EffectSet effects) {
  for (int e = 0; e < kNumEffects; ++e)
    if ((effects & effect_bit(e)) && EffectLibrary::kSides[static_cast<std::size_t>(e)] == HeatSides::both) return true;
  return (side_bits(sides_of_param(i)) & side_bits(EffectLibrary::kSides[static_cast<std::size_t>(effect)])) != 0;
}

}  // namespace lptn::diagnose::internal
