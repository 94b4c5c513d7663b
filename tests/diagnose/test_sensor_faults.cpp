// Sensor faults (trainer/diagnose/sensor_check.hpp): a reading that shifts while the motor stays
// the same. Put into the plant's readings by the generator (an offset of several sizes, one under
// three times the sensor's noise; a gain; a slow drift; without rotor readings too), each must be
// found on the right sensor, with its shape, size and cycles, and nothing physical recommended;
// calibrated around it (the finding's own --sensor-fault), the physical parameters must come back
// within 5 % of the calibration of the same dump without the fault. The other way round, a cooling
// that weakens (the motor changed) and clean dumps must not be called a sensor fault.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "lptn_testing/small_fleet.hpp"
#include "trainer/data/sensor_fault.hpp"
#include "trainer/diagnose/diagnose.hpp"

namespace lptn::diagnose {
namespace {

// Nine cycles of an hour to an hour and a half: a step can only be told from the cycles'
// exchangeable order with enough cycles on either side (the permutation test), and an offset only
// from the initial state's where the cycle outlasts the nodes' time constants.
constexpr int kCycles = 9;

gen::GenerateOptions dump(std::uint64_t seed, std::vector<data::SensorFault> faults, bool rotor = true) {
  gen::GenerateOptions o;
  o.cycles = kCycles;
  o.seed = seed;
  o.sensor_faults = std::move(faults);
  o.rotor_sensor = rotor;
  return o;
}

data::SensorFault fault(data::Channel sensor, data::FaultShape shape, double size, std::size_t first) {
  data::SensorFault f;
  f.sensor = sensor;
  f.shape = shape;
  f.size = size;
  f.first = first;
  return f;
}

std::vector<diagnose::SensorFinding> check(const testing::Generated& g) {
  return diagnose::check_sensors(g.motor.model(), g.calibrated.values, g.dataset, 2);
}

void print(const char* label, const std::vector<diagnose::SensorFinding>& findings) {
  for (const diagnose::SensorFinding& f : findings) {
    std::printf("%s, %s sensor: %s\n   per cycle (reading - model, K):", label, data::sensor_name(f.sensor),
                f.finding.c_str());
    for (const diagnose::CycleOffset& o : f.offsets) std::printf(" %+.2f", o.offset_k);
    std::printf("\n   per cycle (reading gain, %%):");
    for (const diagnose::CycleOffset& o : f.offsets) std::printf(" %+.2f", 100 * o.gain);
    std::printf("\n");
  }
}

const diagnose::SensorFinding* found(const std::vector<diagnose::SensorFinding>& findings) {
  const diagnose::SensorFinding* best = nullptr;
  for (const diagnose::SensorFinding& f : findings)
    if (f.found && (!best || f.p_value < best->p_value)) best = &f;
  return best;
}

std::vector<std::string> cycles_from(const data::Dataset& dataset, std::size_t first) {
  std::vector<std::string> out;
  for (std::size_t i = first; i < dataset.cycles.size(); ++i) out.push_back(dataset.cycles[i].name);
  return out;
}

// The paper's free parameters calibrated on `g`'s dump with `spec` taken out of its readings.
lm::LmReport calibrated_around(const testing::Generated& g, const std::string& spec) {
  data::Dataset corrected = g.dataset;
  data::correct_readings(corrected, std::vector<std::string>{spec});
  return lm::fit_lm(g.motor, g.motor.initial_values(), corrected, g.split.train, lm::LmSettings{});
}

// Every free parameter of `around` within `share` of `clean`'s.
void expect_parameters_near(const model::MotorFile& motor, const lm::LmReport& around, const lm::LmReport& clean, double share,
                            const char* label) {
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(motor);
  for (int i : free.index) {
    const double a = around.values[i], c = clean.values[i];
    std::printf("  %s: %-12s around the fault %9.3f, without it %9.3f (%+.2f %%)\n", label,
                std::string(param_spec(i).name).c_str(), a, c, 100 * (a / c - 1));
    EXPECT_LE(std::abs(a / c - 1), share) << label << ": " << param_spec(i).name;
  }
}

TEST(SensorFaults, AnOffsetIsFoundOnItsSensorFromItsCycleAndCalibratedAround) {
  const auto clean = testing::generate(dump(5, {}));
  // 1 K is under three times the stator sensor's noise (0.4 K).
  for (const double size : {1.0, 3.0, -6.0}) {
    const auto g = testing::generate(dump(5, {fault(data::Channel::stator_winding_c, data::FaultShape::offset, size, 4)}));
    char label[48];
    std::snprintf(label, sizeof label, "offset %+.1f K", size);
    const std::vector<diagnose::SensorFinding> findings = check(*g);
    print(label, findings);
    const diagnose::SensorFinding* f = found(findings);
    ASSERT_NE(f, nullptr) << label;
    EXPECT_EQ(f->sensor, data::Channel::stator_winding_c);
    EXPECT_EQ(f->fault.shape, data::FaultShape::offset);
    EXPECT_EQ(f->cycles, cycles_from(g->dataset, 4));
    EXPECT_NEAR(f->size_k, size, 0.15 * std::abs(size)) << label;
    expect_parameters_near(g->motor, calibrated_around(*g, f->calibrate), clean->calibrated, 0.05, label);
  }
}

TEST(SensorFaults, AGainAndADriftAreFoundWithTheirShape) {
  const auto clean = testing::generate(dump(6, {}));
  struct Case {
    const char* label;
    data::SensorFault fault;
    double size_k_min, size_k_max;
  };
  const Case cases[] = {
      // 4 % of 40..110 °C: 1.6..4.4 K.
      {"gain +4 %", fault(data::Channel::stator_winding_c, data::FaultShape::gain, 0.04, 4), 2.0, 4.0},
      {"drift to +4 K", fault(data::Channel::stator_winding_c, data::FaultShape::drift, 4.0, 2), 3.2, 4.8},
  };
  for (const Case& c : cases) {
    const auto g = testing::generate(dump(6, {c.fault}));
    const std::vector<diagnose::SensorFinding> findings = check(*g);
    print(c.label, findings);
    const diagnose::SensorFinding* f = found(findings);
    ASSERT_NE(f, nullptr) << c.label;
    EXPECT_EQ(f->sensor, c.fault.sensor);
    EXPECT_EQ(f->fault.shape, c.fault.shape) << c.label;
    // Where a gain or a drift begins is known to within a cycle: the first faulty cycle carries a
    // small share of it (a drift's 1/7; a gain's 4 % of a 44 °C shunting cycle, 1.8 K), against the
    // per-cycle scatter of a calibration made on the faulty data (-2.2..+0.4 K before the fault).
    ASSERT_FALSE(f->cycles.empty());
    EXPECT_EQ(f->cycles.back(), g->dataset.cycles.back().name);
    EXPECT_LE(f->cycles.size(), kCycles - c.fault.first) << c.label;
    EXPECT_GE(f->cycles.size() + 1, kCycles - c.fault.first) << c.label;
    EXPECT_GE(f->size_k, c.size_k_min) << c.label;
    EXPECT_LE(f->size_k, c.size_k_max) << c.label;
    expect_parameters_near(g->motor, calibrated_around(*g, f->calibrate), clean->calibrated, 0.05, c.label);
  }
}

TEST(SensorFaults, TheRotorSensorAndAStatorWithoutRotorReadings) {
  {
    const auto g = testing::generate(dump(7, {fault(data::Channel::rotor_c, data::FaultShape::offset, 3.0, 4)}));
    const std::vector<diagnose::SensorFinding> findings = check(*g);
    print("rotor offset +3 K", findings);
    const diagnose::SensorFinding* f = found(findings);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->sensor, data::Channel::rotor_c);
    EXPECT_EQ(f->cycles, cycles_from(g->dataset, 4));
  }
  const auto g = testing::generate(dump(7, {fault(data::Channel::stator_winding_c, data::FaultShape::offset, 3.0, 4)}, false));
  const std::vector<diagnose::SensorFinding> findings = check(*g);
  print("stator offset +3 K, no rotor readings", findings);
  ASSERT_EQ(findings.size(), 1u);  // only the stator is measured
  const diagnose::SensorFinding* f = found(findings);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->cycles, cycles_from(g->dataset, 4));
  EXPECT_NEAR(f->size_k, 3.0, 0.45);
}

// The whole diagnosis of a replaced sensor: the fault stands, outranks the drift the per-cycle
// cooling factors show, and nothing is recommended; the JSON lists it as kind "sensor".
TEST(SensorFaults, TheDiagnosisRecommendsNothingWhileAFaultStands) {
  const auto g = testing::generate(dump(5, {fault(data::Channel::stator_winding_c, data::FaultShape::offset, 3.0, 4)}));
  diagnose::Settings s;
  s.threads = 2;
  const diagnose::Diagnosis d = diagnose::diagnose(g->motor, g->calibrated.values, g->dataset, g->split, s);
  const diagnose::SensorFinding* f = d.sensor_fault();
  ASSERT_NE(f, nullptr);
  std::printf("diagnosis: %s\n", f->finding.c_str());
  EXPECT_EQ(d.best(), nullptr);
  EXPECT_FALSE(d.drift.found);
  for (const diagnose::Candidate& c : d.candidates)
    if (c.verdict == diagnose::Verdict::significant) {
      EXPECT_NE(d.not_recommended_because(c).find("sensor"), std::string::npos);
    }
  const nlohmann::json j = diagnose::to_json(d);
  int sensors = 0;
  for (const auto& c : j.at("candidates")) {
    EXPECT_FALSE(c.at("recommended").get<bool>());
    if (c.at("kind") == "sensor") {
      ++sensors;
      EXPECT_EQ(c.at("sensor"), "stator");
      EXPECT_EQ(c.at("shape"), "offset");
      EXPECT_EQ(c.at("cycles").get<std::vector<std::string>>(), cycles_from(g->dataset, 4));
      EXPECT_NEAR(c.at("size_k").get<double>(), 3.0, 0.45);
    }
  }
  EXPECT_EQ(sensors, 1);
}

// The motor's change is not the sensor's: a cooling that weakens moves both sensors with the load.
// And clean long dumps over five seeds: no fault (the false alarms of the check, measured).
TEST(SensorFaults, AWeakerCoolingAndCleanDumpsAreNoSensorFault) {
  {
    gen::GenerateOptions o = dump(8, {});
    o.plant = gen::plant_bit(gen::PlantPhysics::cooling_fouling);
    const auto g = testing::generate(o);
    const std::vector<diagnose::SensorFinding> findings = check(*g);
    print("cooling_fouling", findings);
    EXPECT_EQ(found(findings), nullptr);
  }
  int faults = 0;
  for (std::uint64_t seed = 11; seed < 16; ++seed) {
    const auto g = testing::generate(dump(seed, {}));
    const std::vector<diagnose::SensorFinding> findings = check(*g);
    char label[32];
    std::snprintf(label, sizeof label, "clean, seed %llu", static_cast<unsigned long long>(seed));
    print(label, findings);
    faults += found(findings) != nullptr;
  }
  std::printf("clean dumps, 5 seeds: %d sensor faults\n", faults);
  EXPECT_EQ(faults, 0);
}

}  // namespace
}  // namespace lptn::diagnose
