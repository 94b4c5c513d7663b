// What diagnose knows about each effect beyond its header: where its score is evaluated and what
// data tells it apart from the paper's parameters.
#pragma once

#include <string_view>

#include "lptn/model.hpp"

namespace lptn::diagnose::internal {

struct EffectNotes {
  std::string_view name;
  // Where the score test evaluates the effect's (first) parameter; NaN: at its neutral value.
  double score_at;
  std::string_view needs;  // the data that separates it from what the model already has
};

inline constexpr double kAtNeutral = __builtin_nan("");

inline constexpr EffectNotes kNotes[] = {
    {"airgap", kAtNeutral,
     "rotor telemetry, and stator and rotor temperatures moving apart (hard acceleration after a soak, or "
     "cycles where rotor and stator losses differ)"},
    {"windage", kAtNeutral, "rotor telemetry, and speed varying independently of load (coasting at speed, light trains at line speed)"},
    {"air_heating", kAtNeutral,
     "cycles at fixed blower levels (airflow not moving with load), with rotor telemetry"},
    {"rotor_speed_convection", kAtNeutral,
     "rotor telemetry, and speed varying independently of airflow and load (fixed or stepped blower levels)"},
    // The lag is tau dTs/dt = T1 - Ts: its neutral tau = 0 is singular (1/tau in the model). Its
    // limit is Ts = T1 - tau dT1/dt, so the score at a small tau (1 ms, below every sensor's and
    // far below the 0.1 s step) is the score at the limit: the sensitivity -dT1/dt.
    {"sensor_lag", 1e-3, "fast load steps (hard acceleration or braking from a steady state), logged at 1 Hz or faster"},
};

// The notes of an effect, or generic ones for an effect without any.
inline EffectNotes notes_for(int effect) {
  const std::string_view name = EffectLibrary::kNames[static_cast<std::size_t>(effect)];
  for (const EffectNotes& n : kNotes)
    if (n.name == name) return n;
  return {name, kAtNeutral, "data in which this effect's inputs vary independently of load and airflow"};
}

}  // namespace lptn::diagnose::internal
