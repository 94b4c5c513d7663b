// What diagnose knows about each effect beyond its header: where its score is evaluated and what
// data tells it apart from the paper's parameters.
#pragma once

#include <string_view>

#include "lptn/model.hpp"

namespace lptn::diagnose::internal {

// The sides of the network an effect's heat flows through (bits): a parameter correlated with the
// effect's but with no heat path to it (the paper leaves stator and rotor unconnected) is not
// confounded with it; the correlation is the fit's ill-conditioning, not physics.
enum Sides : unsigned { kStatorSide = 1, kRotorSide = 2, kBothSides = 3 };

struct EffectNotes {
  std::string_view name;
  // Where the score test evaluates the effect's (first) parameter; NaN: at its neutral value.
  double score_at;
  std::string_view needs;  // the data that separates it from what the model already has
  Sides sides;             // where its heat flows; both where it links the sides (air gap, air heating)
};

inline constexpr double kAtNeutral = __builtin_nan("");

inline constexpr EffectNotes kNotes[] = {
    {"airgap", kAtNeutral,
     "rotor telemetry, and stator and rotor temperatures moving apart (hard acceleration after a soak, or "
     "cycles where rotor and stator losses differ)", kBothSides},
    {"windage", kAtNeutral, "rotor telemetry, and speed varying independently of load (coasting at speed, light trains at line speed)",
     kRotorSide},
    {"air_heating", kAtNeutral,
     "cycles at fixed blower levels (airflow not moving with load), with rotor telemetry", kBothSides},
    {"rotor_speed_convection", kAtNeutral,
     "rotor telemetry, and speed varying independently of airflow and load (fixed or stepped blower levels)",
     kRotorSide},
    // The lag is tau dTs/dt = T1 - Ts: its neutral tau = 0 is singular (1/tau in the model). Its
    // limit is Ts = T1 - tau dT1/dt, so the score at a small tau (1 ms, below every sensor's and
    // far below the 0.1 s step) is the score at the limit: the sensitivity -dT1/dt.
    {"sensor_lag", 1e-3, "fast load steps (hard acceleration or braking from a steady state), logged at 1 Hz or faster",
     kStatorSide},
};

// The notes of an effect, or generic ones for an effect without any (its sides: both, so that every
// correlation counts). A term's sides follow from its node: a path links both, and a cooling term
// on both sides (no node) acts on both.
inline EffectNotes notes_for(int effect) {
  const auto e = static_cast<std::size_t>(effect);
  const std::string_view name = EffectLibrary::kNames[e];
  for (const EffectNotes& n : kNotes)
    if (n.name == name) return n;
  Sides sides = kBothSides;
  if (EffectLibrary::kKinds[e] == EffectKind::term && !name.starts_with("path_") && EffectLibrary::kNodes[e] >= 0)
    sides = EffectLibrary::kNodes[e] < kRotorWinding ? kStatorSide : kRotorSide;
  return {name, kAtNeutral, "data in which this effect's inputs vary independently of load and airflow", sides};
}

// The sides a parameter's heat flows through: a paper parameter's by what it scales (the loss
// shares split a loss between the sides), an effect's by its notes.
inline Sides sides_of_param(int i) {
  switch (i) {
    case kLambda1s: case kLambda2s: case kLambda12s: case kKStemp: return kStatorSide;
    case kLambda1r: case kLambda2r: case kLambda12r: case kKRtemp: return kRotorSide;
    default: break;
  }
  const int effect = effect_of_param(i);
  return effect < 0 ? kBothSides : notes_for(effect).sides;
}

// Whether parameter `i` shares a heat path with `effect` in a model with `effects` enabled: once an
// enabled effect links the sides, every parameter does.
inline bool shares_heat_path(int i, int effect, EffectSet effects) {
  for (int e = 0; e < kNumEffects; ++e)
    if ((effects & effect_bit(e)) && notes_for(e).sides == kBothSides) return true;
  return (sides_of_param(i) & notes_for(effect).sides) != 0;
}

}  // namespace lptn::diagnose::internal
