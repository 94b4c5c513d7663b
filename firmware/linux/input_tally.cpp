#include "input_tally.hpp"

#include <cstdio>

namespace lptn::fw {

void InputTally::add(const EstimatorOutput<double>& o) {
  ++rows;
  for (int i = 0; i < kNumInputs; ++i) {
    const InputMask b = bit(static_cast<Input>(i));
    inputs[i].stale += (o.stale & b) != 0;
    inputs[i].implausible += (o.implausible & b) != 0;
    inputs[i].substituted += (o.substituted & b) != 0;
  }
}

std::vector<std::string> input_warnings(const std::string& log, const InputTally& tally, const EstimatorConfig<double>& config) {
  std::vector<std::string> out;
  const std::size_t rows = tally.rows;
  if (rows == 0) return out;
  auto share = [&](std::size_t n) {
    char text[64];
    std::snprintf(text, sizeof text, "%zu of %zu rows (%.1f %%)", n, rows,
                  100.0 * static_cast<double>(n) / static_cast<double>(rows));
    return std::string(text);
  };
  for (int i = 0; i < kNumInputs; ++i) {
    const InputHealth& h = tally.inputs[i];
    if (h.stale == 0 && h.implausible == 0 && h.substituted == 0) continue;
    const Input input = static_cast<Input>(i);
    const InputLimits<double>& limits = config.inputs[i];
    const char* unit = kInputUnits[i];
    char range[96];
    std::snprintf(range, sizeof range, "%g .. %g %s", limits.min, limits.max, unit);
    std::string line = log + ": input " + kInputNames[i] + " did not reach the model as sent:";
    std::string sep = " ";
    if (h.implausible) {
      line += sep + "implausible (outside " + range + ", its range for the calibration's motor) at " + share(h.implausible);
      sep = "; ";
    }
    if (h.stale) {
      line += sep + "stale (no good value within its timeout) at " + share(h.stale);
      sep = "; ";
    }
    if (h.substituted) {
      char value[64];
      std::snprintf(value, sizeof value, "%g %s", limits.conservative, unit);
      const bool optional = input == Input::torque || input == Input::voltage;
      line += sep +
              (optional ? "left out (the model ran without it) at "
                        : "replaced by its conservative value " + std::string(value) + " at ") +
              share(h.substituted);
    }
    const bool sensor = input == Input::stator_sensor || input == Input::rotor_sensor;
    line += sensor          ? ": those rows went without its readings"
            : h.substituted ? ": the estimates at those rows are not the motor's as the log has it"
                            : ": the model held the last good value there";
    out.push_back(line);
  }
  return out;
}

}  // namespace lptn::fw
