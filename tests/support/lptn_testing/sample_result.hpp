// A calibration result with every field set to something other than its default (shared by the
// calibration-file and export tests).
#pragma once

#include <cmath>
#include <string>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::testing {

// docs/motor.example.toml, the motor file the documentation shows.
inline MotorFile example_motor() { return load_motor_file(LPTN_MOTOR_EXAMPLE); }

inline calibrate::CalibrationResult sample_result(const MotorFile& motor = example_motor()) {
  calibrate::CalibrationResult r;
  r.created_utc = "2026-11-21T10:00:00Z";
  r.lptn_version = "lptn 0.1.0";
  r.motor = motor;
  r.motor.name = "example 4-pole \"traction\" motor";
  r.motor.path = "motors/example.toml";
  r.effects = effect_bit(effect_index("airgap")) | effect_bit(effect_index("sensor_lag"));
  for (int i = 0; i < kNumParams; ++i) {
    const ParamSpec& s = param_spec(i);
    calibrate::ParameterResult p;
    p.name = s.name;
    p.unit = s.unit;
    p.initial = s.initial;
    p.min = s.min;
    p.max = s.max;
    p.value = s.initial * (1 + 0.1 * i) + 1.0 / 3.0;  // not short in decimal: tests full precision
    if (p.value > s.max) p.value = s.max;
    p.calibrated = i % 3 != 2;
    p.std_error = i % 4 == 1 ? std::nan("") : 0.01 * (i + 1) / 7.0;
    r.parameters.push_back(p);
  }
  r.correlated = {{"lambda_1s", "lambda_12s", -0.97}, {"k_stray", "k_harm", 0.951}};
  r.method = "lm";
  r.settings = {{"max_iterations", 100}, {"loss", "squared"}, {"threads", 2}};
  r.details = {{"iterations", 17}, {"final_cost", 12.5}, {"termination", "CONVERGENCE"}};
  r.seconds = 42.25;
  r.data = {{"cycle_01_suburban", "fleet/cycle_01_suburban.csv", std::string(64, 'a')},
            {"cycle_02_freight", "fleet/cycle_02_freight.csv", std::string(64, 'b')}};
  r.data_sha256 = std::string(64, 'c');
  r.train_cycles = {"cycle_01_suburban"};
  r.test_cycles = {"cycle_02_freight"};
  r.split_rule = "--test-cycles cycle_02_freight";
  auto metrics = [](double base, std::size_t samples) {
    ErrorMetrics m;
    m.rmse_k = base;
    m.mean_abs_k = base * 0.8;
    m.max_abs_k = base * 3.1;
    m.bias_k = -base * 0.1;
    m.samples = samples;
    return m;
  };
  r.train.stator = metrics(0.41, 36000);
  r.train.rotor = metrics(0.93, 35000);
  r.train.cycles = {{"cycle_01_suburban", metrics(0.41, 36000), metrics(0.93, 35000)}};
  r.test.stator = metrics(0.52, 30000);  // test cycle without rotor telemetry
  r.test.cycles = {{"cycle_02_freight", metrics(0.52, 30000), ErrorMetrics{}}};
  r.has_actor = true;
  r.actor.obs_offset = {1000.0, 0.0};
  r.actor.obs_scale = {1000.0, 2000.0};
  const int sizes[4] = {2, 3, 3, 2};
  for (int l = 0; l < 3; ++l) {
    calibrate::ActorLayer layer;
    layer.in = sizes[l];
    layer.out = sizes[l + 1];
    for (int k = 0; k < layer.in * layer.out; ++k) layer.weight.push_back(0.1f * static_cast<float>(k - l) + 1e-7f / 3);
    for (int k = 0; k < layer.out; ++k) layer.bias.push_back(-0.05f * static_cast<float>(k + 1) / 3);
    r.actor.layers.push_back(layer);
  }
  r.actor.param_indices = {param_index("lambda_1s"), param_index("airgap_lambda")};
  r.actor.check_obs = {0.5f, -0.25f, 0.1f, 0.9f};
  r.actor.check_actions = {0.125f, -0.3f, 0.7f, 1.0f / 3};
  return r;
}

}  // namespace lptn::testing
