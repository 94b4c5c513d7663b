// The estimator on frames from a synthetic converter: start-up, the open loop against the model
// itself, the Kalman correction, gating, a failed sensor, signal conditioning and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "lptn_testing/converter.hpp"
#include "lptn/firmware/estimator.hpp"
#include "lptn/firmware/output_frames.hpp"

namespace lptn::fw {
namespace {

using testing::Converter;
using testing::DriveState;
using testing::Plant;

constexpr TimeUs kTick = kUsPerS / 10;

EstimatorConfig<double> config_with(const ParamVector<double>& params) {
  return default_config<double>(testing::example_motor(), 0, params);
}

// Runs converter -> estimator for `seconds`, the plant providing the stator reading; hooks may
// change the frames (return false to drop one) or the reading.
struct Bench {
  explicit Bench(const EstimatorConfig<double>& c, const ParamVector<double>& truth = testing::true_params())
      : estimator(std::make_unique<Estimator<double>>(c)), plant(truth, 30.0) {}

  template <class FrameHook>
  void run(double seconds, FrameHook&& hook) {
    const TimeUs end = t + static_cast<TimeUs>(seconds * kUsPerS);
    for (; t < end; t += kTick) {
      DriveState s = testing::drive_at(static_cast<double>(t) / kUsPerS);
      s.stator_c = plant.sensor_reading() + reading_offset;
      if (frozen_reading) s.stator_c = *frozen_reading;
      converter.frames_at(t, s, [&](CanFrame f) {
        if (hook(f)) estimator->receive(f, t);
      });
      const EstimatorOutput<double>& o = estimator->tick(t);
      plant.step(testing::drive_at(static_cast<double>(t) / kUsPerS));
      if (o.initialized) {
        const double e = o.node_c[kStatorWinding] - plant.node(kStatorWinding);
        sum_sq += e * e;
        const double er = o.node_c[kRotorWinding] - plant.node(kRotorWinding);
        sum_sq_rotor += er * er;
        ++n;
      }
    }
  }
  void run(double seconds) {
    run(seconds, [](CanFrame&) { return true; });
  }
  double rmse_stator() const { return std::sqrt(sum_sq / static_cast<double>(n)); }
  double rmse_rotor() const { return std::sqrt(sum_sq_rotor / static_cast<double>(n)); }
  const EstimatorOutput<double>& out() const { return estimator->output(); }

  std::unique_ptr<Estimator<double>> estimator;
  Plant plant;
  Converter converter;
  TimeUs t = 0;
  double reading_offset = 0;
  const double* frozen_reading = nullptr;
  double sum_sq = 0, sum_sq_rotor = 0;
  long n = 0;
};

TEST(Estimator, StartsOnceTheRequiredInputsAndTheStatorReadingAreFresh) {
  Estimator<double> e(config_with(testing::true_params()));
  Converter c;
  const DriveState s = testing::drive_at(0);
  e.receive(c.electrical(s), 0);
  EXPECT_FALSE(e.tick(0).initialized);
  EXPECT_EQ(e.output().mode, Mode::not_initialized);
  CanFrame frames[kMaxOutputFrames];
  EXPECT_EQ(pack_outputs(e.output(), frames), 1) << "before the start only the status frame";
  e.receive(c.cooling(s), kTick);
  e.receive(c.electrical(s), kTick);
  EXPECT_FALSE(e.tick(kTick).initialized) << "no stator reading yet";
  e.receive(c.stator(61.3), 2 * kTick);
  e.receive(c.rotor(70.0), 2 * kTick);
  e.receive(c.electrical(s), 2 * kTick);
  const EstimatorOutput<double>& o = e.tick(2 * kTick);
  ASSERT_TRUE(o.initialized);
  EXPECT_NEAR(o.node_c[kStatorWinding], 61.3, 0.006);
  EXPECT_NEAR(o.node_c[kStatorCore], 61.3, 0.006);
  EXPECT_NEAR(o.node_c[kRotorWinding], 70.0, 0.006) << "the rotor reading starts the rotor nodes";
  EXPECT_NEAR(o.node_c[kRotorCore], 70.0, 0.006);
  EXPECT_LT(o.node_std_k[kStatorWinding], o.node_std_k[kStatorCore]) << "the measured node starts surer";
  EXPECT_EQ(pack_outputs(o, frames), kMaxOutputFrames);

  // Without rotor telemetry the start waits the rotor reading's timeout (3 s), then goes ahead
  // with the rotor nodes at the stator's reading.
  Estimator<double> f(config_with(testing::true_params()));
  Converter d;
  TimeUs t = 0;
  for (; t < 10 * kUsPerS && !f.output().initialized; t += kTick) {
    d.frames_at(t, s, [&](const CanFrame& frame) { f.receive(frame, t); });
    f.tick(t);
  }
  ASSERT_TRUE(f.output().initialized);
  EXPECT_EQ(t - kTick, 3 * kUsPerS);
  EXPECT_NEAR(f.output().node_c[kRotorWinding], f.output().node_c[kStatorWinding], 0.05);
}

// Open loop, the estimator is the model: the same steps on the same (decoded) inputs, bit for bit.
TEST(Estimator, OpenLoopIsTheModelStepForStepOnTheDecodedInputs) {
  EstimatorConfig<double> c = config_with(testing::true_params());
  c.fuse_stator_sensor = false;
  Estimator<double> e(c);
  Converter conv;
  conv.send_rotor = true;  // the rotor's reading starts the rotor nodes at once
  const Model<double> model(testing::example_motor(), 0);
  const ParamVector<double> p = testing::true_params();
  double x[kMaxStates];
  Inputs<double> previous{};
  bool started = false;
  for (TimeUs t = 0; t < 3600 * kUsPerS; t += kTick) {
    DriveState s = testing::drive_at(static_cast<double>(t) / kUsPerS);
    s.stator_c = s.rotor_c = 40.0;
    conv.frames_at(t, s, [&](const CanFrame& f) { e.receive(f, t); });
    const EstimatorOutput<double>& o = e.tick(t);
    ASSERT_TRUE(o.initialized);
    if (!started) {
      model.initial_state(x, 40.0, 40.0);
      started = true;
    } else {
      model.step(x, previous, p.data(), 0.1);
    }
    for (int i = 0; i < kNumNodes; ++i) ASSERT_EQ(o.node_c[i], x[i]) << "node " << i << " at t=" << t;
    previous = testing::decoded_inputs(s, true, true);
    // Airflow and ambient come at 1 s: the estimator holds the last whole second's values.
    const Inputs<double> cooling = testing::decoded_inputs(testing::drive_at(static_cast<double>(t / kUsPerS)), true, true);
    previous.airflow_m3s = cooling.airflow_m3s;
    previous.ambient_c = cooling.ambient_c;
    EXPECT_TRUE(o.torque_route);
    EXPECT_TRUE(o.voltage_route);
  }
  EXPECT_GT(x[kStatorWinding], 60.0) << "the duty heats the motor";
}

// A model 30 % off in the winding's cooling drifts away open loop; the sensor pulls the estimate
// back, and through the network's coupling the unmeasured nodes too.
TEST(Estimator, TheStatorSensorCorrectsABiasedModel) {
  ParamVector<double> biased = testing::true_params();
  biased[kLambda1s] *= 0.7;
  biased[kLambda12s] *= 0.7;
  EstimatorConfig<double> open = config_with(biased), closed = config_with(biased);
  open.fuse_stator_sensor = false;
  Bench a(open), b(closed);
  a.run(2 * 3600.0);
  b.run(2 * 3600.0);
  EXPECT_GT(a.rmse_stator(), 4.0) << "the biased model drifts open loop";
  EXPECT_LT(b.rmse_stator(), 0.25 * a.rmse_stator());
  EXPECT_LT(b.rmse_stator(), 1.0);
  EXPECT_EQ(b.out().sensor, SensorState::fused);
  EXPECT_EQ(b.out().rejected_readings, 0u) << "noise within the gate is never rejected";
  EXPECT_LT(b.out().fusion.test_ratio, 1.0);
  // The published spread covers the actual error most of the time: consistent, not overconfident.
  EXPECT_LT(std::abs(b.out().node_c[kStatorWinding] - b.plant.node(kStatorWinding)), 4 * b.out().node_std_k[kStatorWinding] + 0.5);
}

TEST(Estimator, OpenLoopUncertaintyGrowsAndTheSensorBoundsIt) {
  EstimatorConfig<double> open = config_with(testing::true_params());
  open.fuse_stator_sensor = false;
  Bench a(open), b(config_with(testing::true_params()));
  a.run(1800.0);
  b.run(1800.0);
  EXPECT_GT(a.out().node_std_k[kStatorWinding], 0.5);
  EXPECT_LT(b.out().node_std_k[kStatorWinding], 0.5 * a.out().node_std_k[kStatorWinding]);
  EXPECT_LT(b.out().node_std_k[kStatorWinding], b.out().node_std_k[kRotorWinding]) << "the rotor is not measured";
}

TEST(Estimator, AnOutlierIsRejectedCountedAndLeavesTheEstimateAlone) {
  Bench b(config_with(testing::true_params()));
  b.run(600.0);
  const double before = b.out().node_c[kStatorWinding];
  b.reading_offset = 25.0;
  b.run(1.0);  // one 1 Hz reading 25 K off
  b.reading_offset = 0.0;
  EXPECT_EQ(b.out().sensor, SensorState::rejected);
  EXPECT_EQ(b.out().rejected_readings, 1u);
  EXPECT_GT(b.out().fusion.test_ratio, 1.0);
  EXPECT_GT(b.out().fusion.innovation_k, 20.0);
  EXPECT_NEAR(b.out().node_c[kStatorWinding], before, 0.5);
  CanFrame frames[kMaxOutputFrames];
  ASSERT_EQ(pack_outputs(b.out(), frames), kMaxOutputFrames);
  can::LptnStatus status;
  ASSERT_TRUE(status.unpack(frames[3].data, frames[3].len));
  EXPECT_EQ(status.stator_sensor_state, static_cast<int>(SensorState::rejected));
  EXPECT_EQ(status.rejected_readings, 1);
  b.run(2.0);
  EXPECT_EQ(b.out().sensor, SensorState::fused);
}

TEST(Estimator, ASensorThatKeepsFailingTheGateIsDroppedUntilItAgreesAgain) {
  Bench b(config_with(testing::true_params()));
  b.run(600.0);
  b.reading_offset = 40.0;  // a broken PT100 connection reads 40 K high
  b.run(40.0);
  EXPECT_EQ(b.out().sensor, SensorState::failed_open_loop);
  EXPECT_EQ(b.out().mode, Mode::degraded);
  EXPECT_NEAR(b.out().node_c[kStatorWinding], b.plant.node(kStatorWinding), 1.0) << "open loop, not dragged along";
  b.reading_offset = 0.0;
  b.run(15.0);
  EXPECT_EQ(b.out().sensor, SensorState::fused) << "trusted again after ten good readings";
}

TEST(Estimator, AFrozenSensorIsJudgedStuckWhileTheModelMoves) {
  Bench b(config_with(testing::true_params()));
  b.run(100.0);
  const double frozen = b.plant.sensor_reading();  // plausible when it freezes: the gate alone cannot tell
  b.frozen_reading = &frozen;
  b.run(400.0);  // accelerating and cruising: the winding heats well past 3 K
  EXPECT_EQ(b.out().sensor, SensorState::failed_open_loop);
  b.frozen_reading = nullptr;
  b.run(400.0);
  EXPECT_EQ(b.out().sensor, SensorState::fused);
}

// Cooling health: a motor whose every conductance to the air is `factor` times the calibration's.
ParamVector<double> cooled(double factor) {
  ParamVector<double> p = testing::true_params();
  for (int i : kConductancesToAir) p[i] *= factor;
  return p;
}

// Runs `seconds` in one-minute pieces and says whether the alarm was up at any of their ends.
bool alarmed_during(Bench& b, double seconds) {
  bool any = false;
  for (double done = 0; done < seconds; done += 60.0) {
    b.run(60.0);
    any = any || b.out().cooling_alarm;
  }
  return any;
}

TEST(CoolingHealth, AMotorCooled30PercentWorseIsFoundWithinAnHourAndAlarmed) {
  Bench b(config_with(testing::true_params()), cooled(0.7));
  b.run(3600.0);
  std::printf("after an hour: cooling %.4f +- %.4f (truth 0.7)\n", b.out().cooling_factor, b.out().cooling_factor_std);
  EXPECT_NEAR(b.out().cooling_factor / 0.7, 1.0, 0.05);
  EXPECT_LT(std::abs(b.out().cooling_factor - 0.7), 3 * b.out().cooling_factor_std + 0.01) << "an honest spread";
  EXPECT_EQ(b.out().cooling_state, CoolingState::tracking);
  EXPECT_TRUE(b.out().cooling_alarm);
  CanFrame frames[kMaxOutputFrames];
  ASSERT_EQ(pack_outputs(b.out(), frames), kMaxOutputFrames);
  can::LptnCooling cool;
  ASSERT_TRUE(cool.unpack(frames[5].data, frames[5].len));
  EXPECT_EQ(cool.cooling_alarm, 1);
}

TEST(CoolingHealth, AMotorCooledAsCalibratedRaisesNoAlarm) {
  for (double factor : {1.0, 1.1, 0.9}) {
    Bench b(config_with(testing::true_params()), cooled(factor));
    EXPECT_FALSE(alarmed_during(b, 3600.0)) << factor;
    EXPECT_NEAR(b.out().cooling_factor / factor, 1.0, 0.05) << factor;
  }
}

// Open loop (the sensor judged failed): nothing corrects the factor, so it and its spread stand
// as they were, the frame says frozen, and an alarm raised before stays raised.
TEST(CoolingHealth, OpenLoopFreezesTheEstimateAndFlagsIt) {
  Bench b(config_with(testing::true_params()), cooled(0.7));
  b.run(3600.0);
  ASSERT_TRUE(b.out().cooling_alarm);
  b.reading_offset = 40.0;  // a broken PT100 connection
  b.run(40.0);
  ASSERT_EQ(b.out().sensor, SensorState::failed_open_loop);
  const double factor = b.out().cooling_factor, spread = b.out().cooling_factor_std;
  b.run(1200.0);
  EXPECT_EQ(b.out().cooling_state, CoolingState::frozen);
  EXPECT_EQ(b.out().cooling_factor, factor);
  EXPECT_EQ(b.out().cooling_factor_std, spread);
  EXPECT_TRUE(b.out().cooling_alarm);
  CanFrame frames[kMaxOutputFrames];
  ASSERT_EQ(pack_outputs(b.out(), frames), kMaxOutputFrames);
  can::LptnCooling cool;
  ASSERT_TRUE(cool.unpack(frames[5].data, frames[5].len));
  EXPECT_EQ(cool.cooling_state, static_cast<std::uint8_t>(CoolingState::frozen));
  // The sensor back: tracking again.
  b.reading_offset = 0.0;
  b.run(30.0);
  EXPECT_EQ(b.out().cooling_state, CoolingState::tracking);
}

TEST(CoolingHealth, OffLeavesTheFactorAtOneAndTheModelAsCalibrated) {
  EstimatorConfig<double> c = config_with(testing::true_params());
  c.observer.estimate_cooling = false;
  Bench b(c, cooled(0.7));
  b.run(1800.0);
  EXPECT_EQ(b.out().cooling_state, CoolingState::off);
  EXPECT_EQ(b.out().cooling_factor, 1.0);
  EXPECT_FALSE(b.out().cooling_alarm);
}

TEST(CoolingAlarm, RaisedOnlyWhenSureAndClearedAboveTheBand) {
  CoolingAlarm<double> a;  // raise below 0.80 at 2 sigma, clear above 0.85
  EXPECT_FALSE(a.update(0.75, 0.05, CoolingState::tracking)) << "0.75 + 2 x 0.05 is not sure of below 0.80";
  EXPECT_TRUE(a.update(0.75, 0.02, CoolingState::tracking));
  EXPECT_TRUE(a.update(0.83, 0.02, CoolingState::tracking)) << "inside the band: held";
  EXPECT_TRUE(a.update(0.95, 0.02, CoolingState::frozen)) << "frozen: held";
  EXPECT_FALSE(a.update(0.86, 0.02, CoolingState::tracking));
  EXPECT_FALSE(a.update(0.81, 0.001, CoolingState::tracking)) << "inside the band: stays clear";
  EXPECT_FALSE(a.update(0.5, 0.001, CoolingState::frozen)) << "frozen: stays clear";
}

TEST(Estimator, LostAirflowIsHeldThenReplacedByTheConservativeValue) {
  Bench b(config_with(testing::true_params()));
  b.run(300.0);
  auto drop_cooling = [](CanFrame& f) { return f.id != can::TcCooling::kId; };
  b.run(1.5, drop_cooling);
  EXPECT_EQ(b.out().stale, 0) << "within 3 cycle times";
  b.run(5.0, drop_cooling);
  EXPECT_TRUE(b.out().stale & bit(Input::airflow));
  EXPECT_TRUE(b.out().stale & bit(Input::ambient));
  EXPECT_FALSE(b.out().substituted & bit(Input::airflow)) << "held within the grace period";
  EXPECT_EQ(b.out().mode, Mode::degraded);
  b.run(10.0, drop_cooling);
  EXPECT_TRUE(b.out().substituted & bit(Input::airflow));
  EXPECT_FALSE(b.out().substituted & bit(Input::ambient)) << "ambient's grace is longer";
  EXPECT_EQ(b.out().inputs.airflow_m3s, 0.0);
  EXPECT_EQ(b.out().mode, Mode::conservative);
  b.run(150.0, drop_cooling);
  EXPECT_TRUE(b.out().substituted & bit(Input::ambient));
  EXPECT_EQ(b.out().inputs.ambient_c, 45.0);
  // Open loop the conservative values can only heat the estimate; compare with a run that has them.
  EstimatorConfig<double> open = config_with(testing::true_params());
  open.fuse_stator_sensor = false;
  Bench lost(open), kept(open);
  lost.run(60.0);
  kept.run(60.0);
  lost.run(900.0, drop_cooling);
  kept.run(900.0);
  for (int i = 0; i < kNumNodes; ++i) EXPECT_GT(lost.out().node_c[i], kept.out().node_c[i] + 1.0) << i;
}

TEST(Estimator, LostTorqueAndVoltageFallBackToTheNameplateRoutes) {
  Bench b(config_with(testing::true_params()));
  b.run(10.0);
  EXPECT_TRUE(b.out().torque_route);
  EXPECT_TRUE(b.out().voltage_route);
  auto drop = [](CanFrame& f) { return f.id != can::TcTorque::kId && f.id != can::TcVoltage::kId; };
  b.run(1.0, drop);
  EXPECT_TRUE(b.out().torque_route) << "held";
  b.run(3.0, drop);
  EXPECT_FALSE(b.out().torque_route);
  EXPECT_FALSE(b.out().voltage_route);
  EXPECT_TRUE(b.out().substituted & bit(Input::torque));
  EXPECT_EQ(b.out().mode, Mode::degraded);
  // A converter that never sends them: the nameplate routes from the start, and all is normal.
  Bench c(config_with(testing::true_params()));
  c.converter.send_torque = c.converter.send_voltage = false;
  c.run(10.0);
  EXPECT_FALSE(c.out().torque_route);
  EXPECT_EQ(c.out().substituted, 0);
  EXPECT_EQ(c.out().mode, Mode::normal);
}

// Rewrites an electrical frame's alive counter (and optionally its speed) as a faulty sender would.
void rewrite_electrical(CanFrame& f, int counter, double speed_rpm) {
  can::TcElectrical m;
  m.unpack(f.data, f.len);
  m.alive_counter = static_cast<std::uint8_t>(counter & 0xF);
  m.motor_speed = can::TcElectrical::motor_speed_encode(speed_rpm);
  m.pack(f.data, f.len);
}

TEST(Estimator, FrozenOrSkippingAliveCountersMarkTheirSignalsStaleAndTheirValuesUnused) {
  Bench b(config_with(testing::true_params()));
  b.run(60.0);
  const double speed = b.out().inputs.speed_rpm;
  // Frozen: the converter's task hangs, its counter stands (at the last value sent) while the
  // frame's content changes; that content must not reach the model.
  const int last_sent = (b.converter.counter[0] + 15) & 0xF;
  auto frozen = [&](CanFrame& f) {
    if (f.id == can::TcElectrical::kId) rewrite_electrical(f, last_sent, 4000.0);
    return true;
  };
  b.run(0.3, frozen);
  EXPECT_TRUE(b.out().stale & bit(Input::speed));
  EXPECT_TRUE(b.out().stale & bit(Input::current));
  EXPECT_FALSE(b.out().stale & bit(Input::airflow));
  EXPECT_EQ(b.out().inputs.speed_rpm, speed) << "held, not the frozen frame's value";
  b.run(1.0);
  EXPECT_FALSE(b.out().stale & bit(Input::speed)) << "good counters again";
  // Skipping: every frame's counter jumps by three (frames lost or replayed out of order).
  int counter = b.converter.counter[0];
  auto skipping = [&](CanFrame& f) {
    if (f.id == can::TcElectrical::kId) {
      counter += 3;
      rewrite_electrical(f, counter, 4000.0);
    }
    return true;
  };
  const double held = b.out().inputs.speed_rpm;
  b.run(0.5, skipping);
  EXPECT_TRUE(b.out().stale & bit(Input::speed));
  EXPECT_EQ(b.out().inputs.speed_rpm, held);
}

TEST(Estimator, ImplausibleValuesNeverReachTheModel) {
  Bench b(config_with(testing::true_params()));
  b.run(60.0);
  const double current = b.out().inputs.current_a;
  auto absurd_current = [](CanFrame& f) {
    if (f.id == can::TcElectrical::kId) {  // 0xFFFF * 0.05 A = 3277 A, beyond 4x rated
      f.data[4] = 0xFF;
      f.data[5] = 0xFF;
    }
    return true;
  };
  b.run(1.0, absurd_current);
  EXPECT_TRUE(b.out().implausible & bit(Input::current));
  EXPECT_NEAR(b.out().inputs.current_a, current, 30.0);
  EXPECT_LT(b.out().inputs.current_a, 1000.0);
  b.run(1.0);
  EXPECT_FALSE(b.out().implausible & bit(Input::current));
}

// Frames the DBC does not define, or defines otherwise, are counted and change nothing.
TEST(Estimator, BadFramesAreReportedAndChangeNothing) {
  EstimatorConfig<double> c = config_with(testing::true_params());
  Bench clean(c), noisy(c);
  clean.run(120.0);
  std::mt19937 rng(5);
  std::uint8_t seen = 0;
  noisy.run(120.0, [&](CanFrame& f) {
    CanFrame junk = f;
    switch (rng() % 6) {
      case 0: junk.len = static_cast<std::uint8_t>(junk.len - 1); break;  // wrong DLC
      case 1: junk.id = 0x555; break;                                      // unknown id
      case 2: junk.error = true; break;                                    // error frame
      case 3: junk.remote = true; junk.len = 0; break;                      // remote request
      case 4: junk.fd = true; junk.len = 12; break;                         // CAN FD
      default: junk.extended = true; break;                                 // 29-bit id
    }
    noisy.estimator->receive(junk, noisy.t);
    seen |= noisy.out().bus_events;  // the previous tick's
    return true;
  });
  for (int i = 0; i < kNumNodes; ++i) EXPECT_EQ(noisy.out().node_c[i], clean.out().node_c[i]);
  EXPECT_EQ(seen, bus_event::kWrongLength | bus_event::kUnknownId | bus_event::kErrorFrame);
  EXPECT_EQ(clean.out().bus_events, 0);
}

TEST(Estimator, TimeJumpsAreReportedAndTheEstimateStaysFinite) {
  Bench b(config_with(testing::true_params()));
  b.run(60.0);
  EXPECT_NE(b.estimator->tick(b.t - 30 * kUsPerS).bus_events & bus_event::kTimeBackwards, 0);
  b.t += 600 * kUsPerS;  // then ten minutes ahead
  EXPECT_NE(b.estimator->tick(b.t).bus_events & bus_event::kTimeForwards, 0);
  b.t += kTick;
  b.run(1.0);
  for (int i = 0; i < kNumNodes; ++i) {
    EXPECT_TRUE(std::isfinite(b.out().node_c[i]));
    EXPECT_GT(b.out().node_c[i], -60.0);
    EXPECT_LT(b.out().node_c[i], 400.0);
  }
  b.run(60.0);
  EXPECT_EQ(b.out().mode, Mode::normal);
  EXPECT_EQ(b.out().bus_events, 0);
}

// Full bus load of random frames between the converter's: it keeps running, finite and bounded.
TEST(Estimator, SurvivesABusFullOfRandomFrames) {
  Bench b(config_with(testing::true_params()));
  std::mt19937 rng(11);
  b.run(600.0, [&](CanFrame&) {
    for (int k = 0; k < 250; ++k) {  // ~8000 frames per 100 ms tick at 1 Mbit/s would be the limit
      CanFrame f;
      f.id = rng() & 0x7FF;
      f.len = static_cast<std::uint8_t>(rng() % 9);
      for (auto& d : f.data) d = static_cast<std::uint8_t>(rng());
      f.extended = rng() % 8 == 0;
      b.estimator->receive(f, b.t);
    }
    return true;
  });
  for (int i = 0; i < kNumNodes; ++i) {
    EXPECT_TRUE(std::isfinite(b.out().node_c[i]));
    EXPECT_GT(b.out().node_c[i], -60.0);
    EXPECT_LT(b.out().node_c[i], 400.0);
    EXPECT_TRUE(std::isfinite(b.out().node_std_k[i]));
  }
  EXPECT_TRUE(b.out().initialized);
}

TEST(Estimator, OutputFramesCarryTheEstimate) {
  Bench b(config_with(testing::true_params()));
  b.run(900.0);
  CanFrame frames[kMaxOutputFrames];
  ASSERT_EQ(pack_outputs(b.out(), frames), kMaxOutputFrames);
  can::LptnTemperatures t;
  can::LptnTemperatureStd s;
  can::LptnMargin m;
  can::LptnInnovation in;
  can::LptnCooling cool;
  ASSERT_TRUE(t.unpack(frames[0].data, frames[0].len));
  ASSERT_TRUE(s.unpack(frames[1].data, frames[1].len));
  ASSERT_TRUE(m.unpack(frames[2].data, frames[2].len));
  ASSERT_TRUE(in.unpack(frames[4].data, frames[4].len));
  ASSERT_TRUE(cool.unpack(frames[5].data, frames[5].len));
  // Within half a step of each signal's resolution (the DBC's factor): the encoders round.
  const double half_temp = can::LptnTemperatures::kSignals[2].factor / 2;
  const double half_std = can::LptnTemperatureStd::kSignals[2].factor / 2;
  const double half_margin = can::LptnMargin::kSignals[3].factor / 2;
  EXPECT_NEAR(can::LptnTemperatures::stator_winding_temp_decode(t.stator_winding_temp), b.out().node_c[0], half_temp + 1e-12);
  EXPECT_NEAR(can::LptnTemperatures::rotor_core_temp_decode(t.rotor_core_temp), b.out().node_c[3], half_temp + 1e-12);
  EXPECT_NEAR(can::LptnTemperatureStd::rotor_winding_std_decode(s.rotor_winding_std), b.out().node_std_k[2], half_std + 1e-12);
  EXPECT_EQ(m.limiting_node, b.out().limiting_node);
  EXPECT_NEAR(can::LptnMargin::margin_decode(m.margin), b.out().margin_k, half_margin + 1e-12);
  EXPECT_LT(can::LptnMargin::margin_conservative_decode(m.margin_conservative), can::LptnMargin::margin_decode(m.margin));
  EXPECT_EQ(in.observer_ticks, b.out().ticks & 0xFFFF);
  EXPECT_EQ(frames[0].id, 0x200u);
  EXPECT_EQ(frames[4].id, 0x204u);
  const double half_factor = can::LptnCooling::kSignals[2].factor / 2;
  EXPECT_NEAR(can::LptnCooling::cooling_factor_decode(cool.cooling_factor), b.out().cooling_factor, half_factor + 1e-12);
  EXPECT_NEAR(can::LptnCooling::cooling_factor_std_decode(cool.cooling_factor_std), b.out().cooling_factor_std,
              half_factor + 1e-12);
  EXPECT_GT(b.out().cooling_factor_std, 0.0);
  EXPECT_EQ(cool.cooling_state, static_cast<std::uint8_t>(CoolingState::tracking));
  EXPECT_EQ(cool.cooling_alarm, 0);
  EXPECT_EQ(frames[5].id, 0x205u);
}

// End-to-end protection of the outputs (e2e.hpp): every frame's CRC checks over its data id (the
// DBC's id) and the other bytes, a changed byte or another data id fails it, and each message's
// counter counts its frames.
TEST(Estimator, EveryOutputFrameIsEndToEndProtected) {
  Bench b(config_with(testing::true_params()));
  b.run(60.0);
  CanFrame before[kMaxOutputFrames], after[kMaxOutputFrames];
  ASSERT_EQ(pack_outputs(b.out(), before), kMaxOutputFrames);
  b.run(0.1);
  ASSERT_EQ(pack_outputs(b.out(), after), kMaxOutputFrames);
  for (int i = 0; i < kMaxOutputFrames; ++i) {
    const CanFrame& f = after[i];
    const auto id = static_cast<std::uint16_t>(f.id);
    EXPECT_EQ(f.data[0], e2e::frame_crc(id, f.data, f.len, 0)) << "frame " << f.id;
    CanFrame bad = f;
    bad.data[5] ^= 0x10;
    EXPECT_NE(bad.data[0], e2e::frame_crc(id, bad.data, bad.len, 0)) << "frame " << f.id;
    EXPECT_NE(f.data[0], e2e::frame_crc(static_cast<std::uint16_t>(id + 1), f.data, f.len, 0)) << "frame " << f.id;
    // The counter: byte 1's low nibble in every LPTN_* frame, one up from the tick before.
    EXPECT_EQ(f.data[1] & 0xF, (before[i].data[1] + 1) & 0xF) << "frame " << f.id;
  }
  can::LptnStatus status;
  ASSERT_TRUE(status.unpack(after[3].data, after[3].len));
  EXPECT_EQ(status.status_counter, b.out().status_counter);
}

// A bus map's [outputs] moves the frames to other CAN ids; the payload, and the CRC over the
// DBC's id as data id, stay what they were.
TEST(Estimator, OutputFramesGoOutOnTheIdsGiven) {
  Bench b(config_with(testing::true_params()));
  b.run(60.0);
  const OutputId moved[kMaxOutputFrames] = {{0x18FF4027u, true}, {0x18FF4127u, true}, {0x300u, false},
                                            {0x301u, false}, {0x7FFu, false}, {0x18FF4227u, true}};
  CanFrame dbc_ids[kMaxOutputFrames], other_ids[kMaxOutputFrames];
  ASSERT_EQ(pack_outputs(b.out(), dbc_ids), kMaxOutputFrames);
  ASSERT_EQ(pack_outputs(b.out(), other_ids, moved), kMaxOutputFrames);
  for (int i = 0; i < kMaxOutputFrames; ++i) {
    EXPECT_EQ(dbc_ids[i].id, kOutputFrames[i].dbc.id);
    EXPECT_EQ(other_ids[i].id, moved[i].id);
    EXPECT_EQ(other_ids[i].extended, moved[i].extended);
    EXPECT_EQ(other_ids[i].len, dbc_ids[i].len);
    EXPECT_EQ(0, std::memcmp(other_ids[i].data, dbc_ids[i].data, dbc_ids[i].len)) << kOutputFrames[i].name;
    EXPECT_EQ(other_ids[i].data[0],
              e2e::frame_crc(static_cast<std::uint16_t>(kOutputFrames[i].dbc.id), other_ids[i].data, other_ids[i].len, 0));
  }
}

TEST(E2E, Crc8SaeJ1850HasItsCatalogueCheckValue) {
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(e2e::crc8_j1850(check, 9), 0x4B);  // reveng's catalogue: CRC-8/SAE-J1850, check=0x4b
  EXPECT_EQ(e2e::crc8_j1850(check, 0), 0x00);  // init 0xFF, xorout 0xFF
}

TEST(E2E, CountersTolerateLostFramesUpToMaxDelta) {
  e2e::CounterState c;
  EXPECT_EQ(c.step(14, 16, 2), e2e::CounterCheck::first);
  EXPECT_EQ(c.step(15, 16, 2), e2e::CounterCheck::ok);
  EXPECT_EQ(c.step(1, 16, 2), e2e::CounterCheck::lost);      // 0 lost, wrapping
  EXPECT_EQ(c.step(1, 16, 2), e2e::CounterCheck::repeated);  // the same frame again
  EXPECT_EQ(c.step(4, 16, 2), e2e::CounterCheck::jumped);    // two lost: beyond MaxDeltaCounter 2
  EXPECT_EQ(c.step(5, 16, 2), e2e::CounterCheck::ok);        // back in step after the jump
  EXPECT_EQ(c.step(8, 16, 3), e2e::CounterCheck::lost);      // two lost: within MaxDeltaCounter 3
}

// A hand-made actor (2 -> 4 -> 4 -> 1) that drives lambda_1s from speed: the schedule follows
// speed while torque is on the bus, and the constant set stands without it.
TEST(Estimator, TheActorSchedulesItsParametersFromSpeedAndTorque) {
  static const float w1[8] = {1, 0, -1, 0, 0.5f, 0, 0, 0}, b1[4] = {0, 0, 0, 0};
  static const float w2[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, b2[4] = {0, 0, 0, 0};
  static const float w3[4] = {1, -1, 0, 0}, b3[1] = {0};
  static const ActorView actor{2, 4, 1, w1, b1, w2, b2, w3, b3};
  static const int index[1] = {kLambda1s};
  static const double lo[1] = {1.0}, hi[1] = {1000.0};
  EstimatorConfig<double> c = config_with(testing::true_params());
  c.fuse_stator_sensor = false;  // open loop, so that the parameters alone make the difference
  EstimatorConfig<double> constant = c;
  c.use_actor = true;
  c.actor.actor = &actor;
  c.actor.obs_scale[0] = 1950.0;
  c.actor.obs_scale[1] = 1500.0;
  c.actor.param_index = index;
  c.actor.param_min = lo;
  c.actor.param_max = hi;
  Bench scheduled(c), fixed(constant);
  scheduled.run(300.0);  // accelerating, then cruising at 1800 rpm: u = tanh(0.92), lambda_1s ~ 330 W/K
  fixed.run(300.0);
  EXPECT_TRUE(scheduled.out().actor_scheduling);
  EXPECT_FALSE(fixed.out().actor_scheduling);
  EXPECT_LT(scheduled.out().node_c[kStatorWinding], fixed.out().node_c[kStatorWinding] - 1.0)
      << "a much larger winding conductance runs cooler";
  Bench no_torque(c);
  no_torque.converter.send_torque = false;
  no_torque.run(100.0);
  EXPECT_FALSE(no_torque.out().actor_scheduling) << "the actor observes torque";
}

}  // namespace
}  // namespace lptn::fw
