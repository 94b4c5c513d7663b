// A verdict on the model itself, per sensor, before any candidate is tried: is what is left of
// the residual the sensor's own noise, or structure the model does not explain? A diagnosis that
// finds no candidate of the library significant must not then say "no reason to add one" while
// the model is several times its sensors' noise off: something is missing that the library lacks.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::diagnose {

// How far above its noise a sensor's RMSE may be before the model counts as missing something.
// A model that is right leaves the noise alone: on the 10 Hz grid, between the 1 Hz readings it
// interpolates, the RMSE is 0.8 to 1.0 times the noise (at most 0.97 over five seeds of clean data
// in tests/diagnose). At 1.5 times, the model's own error is at least as large as the noise
// (sqrt(1.5^2 - 1^2) = 1.1).
inline constexpr double kAdequateRatio = 1.5;

// Where a sensor's residual lies (internal/where.hpp): the inputs it follows, each through a
// 10-minute first-order lag (a thermal residual answers an input's recent history), and the speed x
// current tertile where it is largest.
struct Follows {
  std::string input;       // "speed", "current", "torque", "frequency", "airflow", "ambient"
  double correlation = 0;  // of the residual (model - measured) with the lagged input; > 0: model too hot as it rises
};
struct Where {
  std::vector<Follows> follows;  // |correlation| >= 0.3, strongest first, at most 3
  std::string region;            // e.g. "high speed (1700..2500 1/min), low current (0..180 A)"; "" if none
  double region_rmse_k = 0;      // the residual's RMS there
  double region_share = 0;       // the share of the sensor's readings there
};

// The residual's shape in time (internal/where.hpp): how long it stays correlated and what it moves
// with besides the inputs. What a user is told when no candidate explains a residual
// (shape_in_words): a slow residual that grows while the motor warms is a missing heat store, not a
// missing loss; one faster than any node is the sensor's, not the motor's.
// A residual correlated for less than this is faster than any node of the model (the windings'
// time constants are minutes): the sensor's own dynamics, not the motor's heat.
inline constexpr double kFastResidualS = 60;
// One correlated for longer than this is slow: beyond a load change's response.
inline constexpr double kSlowResidualS = 600;
struct Shape {
  double correlation_time_s = 0;  // where the residual's autocorrelation falls below 1/e (NaN: too few readings)
  bool correlation_time_at_least = false;  // it had not fallen by the longest lag measured: a lower bound
  double mean_k = 0;                        // the residual's mean (model - measured)
  // The readings over the residual's own spacing of independence, 2 x its correlation time: what a
  // correlation with it rests on. A correlation is worded only beyond 2 / sqrt(this) (and
  // internal::kFollowMin): four 90-minute cycles of a residual correlated for 20 minutes are nine
  // independent samples, on which r = 0.4 with any slow input is chance.
  double effective_readings = 0;
  double with_warming = 0;  // correlation with the sensor's own rate of warming over kWarmingWindowS (NaN: none)
  double with_rise = 0;     // correlation with the sensor's reading above ambient (NaN: none)
};

struct SensorAdequacy {
  std::string sensor;            // "stator" (winding sensor) or "rotor"
  double train_rmse_k = 0, test_rmse_k = 0;  // test: NaN without test cycles
  double noise_k = 0;            // estimated from the residual at the sensor's readings
  double unexplained = 0;        // share of the mean-square residual the noise does not explain, worst side
  bool adequate = true;          // RMSE within kAdequateRatio x noise on train and test
  std::vector<std::string> cycles;  // where it is not: the cycles beyond the ratio, worst first
  Where where;                      // over every cycle, train and test
  Shape shape;                      // likewise
};

struct Adequacy {
  bool adequate = true;  // every measured sensor is
  std::vector<SensorAdequacy> sensors;  // the measured ones
  // The simulation's metrics, per cycle and pooled, as evaluate_split gives them (the diagnosis's
  // "before" figures read them instead of simulating the cycles again).
  calibrate::SplitMetrics train, test;
};

// Simulates every cycle of the split at `params` once (offsets as the metrics estimate them).
Adequacy assess_adequacy(const Model<double>& model, const ParamVector<double>& params, calibrate::DatasetRef dataset,
                         const calibrate::Split& split, int threads);

// {"adequate": bool, "adequate_within": 1.5, "sensors": {"stator": {"rmse_k", "noise_k", "adequate",
// "train_rmse_k", "test_rmse_k", "unexplained", "cycles", "follows": [{"input", "correlation"}],
// "region": {"name", "rmse_k", "share"} or null}, "rotor": {...}}}; rmse_k is the worse of train and test.
nlohmann::json to_json(const Adequacy& adequacy);

// The smallest correlation with the residual that is more than chance on its independent samples:
// 2 / sqrt(effective_readings), and never below internal::kFollowMin (0.3). The shape's words
// name only correlations at least this large (Where::follows lists every one from 0.3, with its r).
double least_telling_correlation(const Shape& shape);

// What the residual's shape suggests, in words, for a sensor that is not adequate and where no
// candidate explains it, e.g. "the residual stays correlated for 17 min and is largest while the
// motor warms (r = +0.71): the model warms and cools faster than the motor, as where heat is stored
// in a mass the model lacks (a frame, a housing): a thermal mass (mass_*), if the dictionary has one
// on this side". Empty for an adequate sensor.
std::string shape_in_words(const SensorAdequacy& sensor);

// One line per sensor for the command line, e.g. "rotor: test RMSE 8.15 K = 16.3x its noise of
// 0.50 K: something is missing (cycles a, b)".
std::string describe(const SensorAdequacy& sensor);

}  // namespace lptn::diagnose
