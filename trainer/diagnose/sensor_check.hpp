// Sensor faults: does one reading shift between cycles while the motor stays the same?
//
// A replaced sensor reads 3 K high from some cycle on; a transmitter's span drifts; an ageing
// sensor creeps. The motor did not change, yet a calibration or an effect would absorb the shift
// as physics (a heat source of 262 W, a cooling 7 % weaker) and make the model wrong against the
// real temperature. So, before any candidate, for each measured temperature sensor:
//
//   per cycle   the reading offset that fits the cycle best (b_i, K), and separately the reading
//               gain (g_i), each beside the cycle's initial offsets refit over the whole cycle: the
//               model is affine in its initial state, and an offset of the readings also moves the
//               start (each measured node starts at its reading), so one simulation per column
//               gives the cycle's least-squares problem exactly. (With the offsets fitted on the
//               first ten minutes only, as the metrics do, a warmer start takes up most of a
//               constant offset.) M_i, the model's mean temperature at the readings, °C.
//   the shapes  over the cycles in the dump's order (trainer/data/sensor_fault.hpp): an offset
//               from cycle k on, b_i = c + a [i >= k]; a gain from cycle k on, g_i = c + g [i >= k];
//               a drift growing from cycle k, b_i = c + a w_i(k). Each fitted by least squares, k
//               over every cycle with two on either side (a drift may start at the first).
//   the test    the largest reduction of a series' squared deviation over shapes and k, in units of
//               what is left (at least kOffsetResolution per cycle); its p-value exact under "no
//               fault" (the cycles exchangeable): the share of 4,000 random orderings of the cycles
//               whose largest reduction reaches it. Bonferroni over the sensors checked.
//   the motor   a sensor fault moves one reading and nothing else. Over the faulty cycles, the
//               squared error of every measured sensor with each cycle's own offset (or gain) of
//               this sensor must be below that with each cycle's own cooling factor and with each
//               cycle's own copper-loss factor (linearized in the log factor, beside the same
//               initial offsets): a change of the heat balance moves both sensors and follows the
//               load; a sensor's does neither.
// A fault is found when p <= kSensorLevel / sensors, its size is at least kMinSensorFaultK and the
// heat balance explains the faulty cycles worse than the sensor. Like a drift it is a finding, not
// an effect: while one stands nothing physical is recommended.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/data/sensor_fault.hpp"

namespace lptn::diagnose {

inline constexpr double kSensorLevel = 0.05;
// The smallest fault reported, K (for a gain: its mean error over the faulty cycles). Below this a
// per-cycle shift is within what the model's own misfit between kinds of cycle makes.
inline constexpr double kMinSensorFaultK = 0.5;
// A cycle's mean offset is not more precise than this, whatever its fit says (K).
inline constexpr double kOffsetResolution = 0.05;

struct CycleOffset {
  std::string cycle;
  double offset_k = 0;  // the reading's offset that fits the cycle best (b_i, K)
  double gain = 0;      // the reading's gain that fits it best, separately (g_i, relative)
  double mean_c = 0;    // the model's mean temperature at the readings (M_i)
};

struct SensorFinding {
  data::Channel sensor = data::Channel::stator_winding_c;
  std::vector<CycleOffset> offsets;  // every cycle that has this sensor's readings, in the dump's order
  bool found = false;
  data::SensorFault fault;  // the best shape: its size (K; relative for a gain) and first cycle
  double size_k = 0;        // in K: the offset, the drift's in the last cycle, the gain's mean over the faulty cycles
  double statistic = 0;
  double p_value = 1;
  double level = kSensorLevel;      // what p is held to (Bonferroni over the sensors)
  std::vector<std::string> cycles;  // the faulty cycles
  // Over the faulty cycles, every measured sensor's squared error (K^2) with each cycle's own fit of
  // this sensor's shape, of the cooling factor and of the copper-loss factor (0: not computed).
  double sse_sensor = 0, sse_cooling = 0, sse_losses = 0;
  std::string finding;   // "the stator sensor reads 3.0 K high from cycle_05_freight on ..." (or why it is not a fault)
  std::string inspect;   // what to do
  std::string calibrate;  // the --sensor-fault argument that calibrates around it
};

// Every measured temperature sensor checked at `params` (the baseline), in channel order.
std::vector<SensorFinding> check_sensors(const Model<double>& model, const ParamVector<double>& params,
                                         const data::Dataset& dataset, int threads);

// {"sensor", "found", "shape", "size", "size_k", "first_cycle", "cycles", "p_value", "level", "finding",
//  "inspect", "calibrate", "heat_balance": {...}, "offsets": [{"cycle", "offset_k", "mean_c"}]}
nlohmann::json to_json(const SensorFinding& finding);

}  // namespace lptn::diagnose
