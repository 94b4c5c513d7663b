// The Levenberg-Marquardt fit on data the model can describe exactly (no hidden effect): it must
// find the plant's true conductances and fit unseen cycles to the sensors' noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "hostio/bad_input.hpp"
#include "lptn_testing/fleet_dump.hpp"
#include "simulator/generate/generate.hpp"
#include "simulator/generate/plant_truth.hpp"
#include "trainer/lm/lm.hpp"
#include "trainer/model/initial_offsets.hpp"
#include "trainer/model/motor_effects.hpp"
#include "trainer/model/simulate.hpp"

#include <ceres/ceres.h>

namespace lptn::lm {
namespace {

// Nine cycles (as the benchmark), shorter than the default so the test takes seconds.
const testing::Dump& generated() {
  static const testing::Dump* f = [] {
    auto* d = new testing::Dump;
    testing::generate_dump(*d, 9, 7, 1800, 2700, 1.0 / 3.0);
    return d;
  }();
  return *f;
}

TEST(LevenbergMarquardt, RecoversTrueConductancesAndFitsUnseenCyclesToTheNoise) {
  const testing::Dump& f = generated();
  ASSERT_EQ(f.split.train.size(), 6u);
  ASSERT_EQ(f.split.test.size(), 3u);
  const ParamVector<double> start = f.motor.initial_values();
  const lm::LmReport r = lm::fit_lm(f.motor, start, f.dataset, f.split.train, lm::LmSettings{});
  const ParamVector<double> truth = gen::true_parameters();
  for (int i = 0; i < kNumPaperParams; ++i) {
    if (!f.motor.parameters[static_cast<std::size_t>(i)].calibrate) continue;
    EXPECT_NEAR(r.values[i] / truth[i], 1.0, 0.05) << param_spec(i).name << " start " << start[i];
    // The starting guess was not already there: the fit moved it.
    EXPECT_GT(std::abs(start[i] / truth[i] - 1.0), 0.05) << param_spec(i).name;
  }
  const Model<double> model = f.motor.model();
  const calibrate::SplitMetrics test = calibrate::evaluate_split(model, r.values, f.dataset, f.split.test);
  const calibrate::SplitMetrics before = calibrate::evaluate_split(model, start, f.dataset, f.split.test);
  EXPECT_LT(test.stator.rmse_k, 1.5 * 0.4);
  EXPECT_LT(test.rotor.rmse_k, 1.5 * 0.5);
  EXPECT_GT(before.stator.rmse_k, 5 * test.stator.rmse_k);
  std::printf("LM: %d iterations, %.2f s, train RMSE %.3f K, test stator %.3f K rotor %.3f K (before %.3f K)\n",
              r.iterations, r.seconds, r.rmse_k, test.stator.rmse_k, test.rotor.rmse_k, before.stator.rmse_k);
}

// A dataset's prepared inputs (SharedDataset::prepared, what diagnose's fits on the 1 s grid share)
// give the fit the bits it finds preparing every step itself, for the paper's model and for one
// with an effect (effects do not enter the prepared inputs); prepared with another motor's
// constants they move it, so the fit does read them.
TEST(LevenbergMarquardt, PreparedInputsGiveTheFitItsOwnBits) {
  const testing::Dump& f = generated();
  calibrate::SharedDataset plain{f.dataset, {}, {}};
  auto prepared_with = [&](const model::MotorFile& motor) {
    calibrate::SharedDataset d{f.dataset, {}, {}};
    d.prepared.resize(d.data.cycles.size());
    for (std::size_t c : f.split.train) d.prepared[c] = model::prepare_cycle(motor.model(), d.data.cycles[c]);
    return d;
  };
  const calibrate::SharedDataset prepared = prepared_with(f.motor);
  ASSERT_NE(calibrate::DatasetRef(prepared).prepared(f.split.train[0]), nullptr);
  ASSERT_EQ(calibrate::DatasetRef(plain).prepared(f.split.train[0]), nullptr);
  model::MotorFile windage = f.motor;
  model::enable_effect(windage, effect_index("windage"));
  ASSERT_NE(windage.effects, f.motor.effects);
  lm::LmSettings settings;
  settings.max_iterations = 4;
  const model::MotorFile* motors[] = {&f.motor, &windage};
  for (const model::MotorFile* motor : motors) {
    const ParamVector<double> start = motor->initial_values();
    const lm::LmReport a = lm::fit_lm(*motor, start, plain, f.split.train, settings);
    const lm::LmReport b = lm::fit_lm(*motor, start, prepared, f.split.train, settings);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.final_cost, b.final_cost);
    for (int i = 0; i < kNumParams; ++i) EXPECT_EQ(a.values[i], b.values[i]) << param_spec(i).name;
    for (std::size_t c = 0; c < a.offsets.size(); ++c) {
      EXPECT_EQ(a.offsets[c].stator_core, b.offsets[c].stator_core);
      EXPECT_EQ(a.offsets[c].rotor_core, b.offsets[c].rotor_core);
    }
  }
  model::MotorFile other = f.motor;
  other.constants.stator_resistance_20c_ohm *= 2;
  const calibrate::SharedDataset wrong = prepared_with(other);
  const ParamVector<double> start = f.motor.initial_values();
  EXPECT_NE(lm::fit_lm(f.motor, start, plain, f.split.train, settings).final_cost,
            lm::fit_lm(f.motor, start, wrong, f.split.train, settings).final_cost);
}

TEST(LevenbergMarquardt, ReportsStandardErrorsThatCoverTheTruth) {
  const testing::Dump& f = generated();
  const lm::LmReport r = lm::fit_lm(f.motor, f.motor.initial_values(), f.dataset, f.split.train, lm::LmSettings{});
  const ParamVector<double> truth = gen::true_parameters();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(f.motor);
  for (std::size_t j = 0; j < free.size(); ++j) {
    const int i = free.index[j];
    ASSERT_TRUE(std::isfinite(r.std_error[i])) << param_spec(i).name;
    EXPECT_GT(r.std_error[i], 0.0) << param_spec(i).name;
    // White sensor noise only: the error is a few standard errors at most (generous: 10 sigma).
    EXPECT_LT(std::abs(r.values[i] - truth[i]), 10 * r.std_error[i] + 1e-3 * truth[i]) << param_spec(i).name;
  }
}

TEST(LevenbergMarquardt, FlagsParametersTheDataCannotTellApart) {
  // Without the rotor sensor the rotor's conductances are seen only through the stator winding,
  // which the paper's network does not connect to the rotor at all: they are unidentifiable.
  testing::TempDir dir;
  gen::GenerateOptions o;
  o.cycles = 3;
  o.seed = 3;
  o.min_duration_s = 900;
  o.max_duration_s = 1200;
  o.rotor_sensor = false;
  gen::generate(o, dir.path());
  const data::Dataset d = data::load_fleet_dump({dir.path()});
  model::MotorFile motor = model::load_motor_file(dir.path() / "motor.toml");
  std::vector<std::size_t> all{0, 1, 2};
  const lm::LmReport r = lm::fit_lm(motor, motor.initial_values(), d, all, lm::LmSettings{});
  bool rotor_flagged = false;
  for (const calibrate::CorrelatedPair& p : r.correlated) rotor_flagged |= p.a.find("r") != std::string::npos;
  const int rotor_param = param_index("lambda_1r");
  EXPECT_TRUE(rotor_flagged || !std::isfinite(r.std_error[rotor_param]));
}

// The estimate of where the unmeasured nodes start, against the plant's truth: the generator's
// motors start soaked through, so the stator core starts where the winding does, not where its
// first noisy reading says.
TEST(InitialOffsets, EstimateFindsTheUnmeasuredNodesTrueStart) {
  const testing::Dump& f = generated();
  const Model<double> model = f.motor.model();
  const ParamVector<double> truth = gen::true_parameters();
  double rule_error = 0, estimate_error = 0, rule_sum = 0, estimate_sum = 0;
  for (const data::Cycle& cycle : f.dataset.cycles) {
    std::ifstream in(f.dir.path() / "truth" / (cycle.name + ".csv"));
    std::string header, first;
    std::getline(in, header);
    std::getline(in, first);
    double t, winding, core, rotor_winding, rotor_core;
    ASSERT_EQ(std::sscanf(first.c_str(), "%lf,%lf,%lf,%lf,%lf", &t, &winding, &core, &rotor_winding, &rotor_core), 5);
    double x[kMaxStates];
    model::initial_state_for(model, cycle, x);  // the rule alone
    const model::InitialOffsets<double> o = model::estimate_initial_offsets(model, truth, cycle);
    rule_error = std::max(rule_error, std::abs(x[kStatorCore] - core));
    estimate_error = std::max(estimate_error, std::abs(x[kStatorCore] + o.stator_core - core));
    rule_sum += std::abs(x[kStatorCore] - core);
    estimate_sum += std::abs(x[kStatorCore] + o.stator_core - core);
    EXPECT_NEAR(x[kRotorCore] + o.rotor_core, rotor_core, 0.5) << cycle.name;
  }
  std::printf("stator core start over 9 cycles: rule %.3f K off on average (worst %.3f K), estimate %.3f K (worst %.3f K)\n",
              rule_sum / 9, rule_error, estimate_sum / 9, estimate_error);
  // The estimate also absorbs the winding's own start (its first reading, noise 0.4 K), so it is
  // not exact; it must beat the rule and stay within the sensor's noise.
  EXPECT_LT(estimate_sum, rule_sum);
  EXPECT_LT(estimate_error, 0.6);
}

// The reference for the closed form: the bounded least-squares problem solved iteratively in Ceres
// (as the offsets were before), its Jacobian by automatic differentiation through the simulation.
struct OffsetResiduals {
  const Model<double>& model;
  const ParamVector<double>& params;
  const data::Cycle& cycle;
  std::size_t steps;
  template <class T>
  bool operator()(T const* const* offsets, T* r) const {
    std::size_t n = 0;
    ParamVector<T> p;
    for (int i = 0; i < kNumParams; ++i) p[i] = T(params[i]);
    model::run_cycle(model, p.data(), cycle, [&](std::ptrdiff_t k, const T* x) {
      if (k < 0) return;
      const auto grid = static_cast<std::size_t>(k + 1);
      const float ys = cycle.at(data::Channel::stator_winding_c, grid), yr = cycle.at(data::Channel::rotor_c, grid);
      if (!std::isnan(ys)) r[n++] = model.stator_sensor(x) - T(ys);
      if (!std::isnan(yr)) r[n++] = model.rotor_sensor(x) - T(yr);
    }, model::InitialOffsets<T>{offsets[0][0], offsets[0][1]}, steps);
    return true;
  }
};

// The sum of squared residuals over the window at given offsets (the objective both minimize).
double window_cost(const Model<double>& model, const ParamVector<double>& params, const data::Cycle& cycle,
                   const model::InitialOffsets<double>& o) {
  const std::size_t steps = static_cast<std::size_t>(600.0 / cycle.dt_s);
  double cost = 0;
  model::run_cycle(model, params.data(), cycle, [&](std::ptrdiff_t k, const double* x) {
    if (k < 0) return;
    const auto grid = static_cast<std::size_t>(k + 1);
    const float ys = cycle.at(data::Channel::stator_winding_c, grid), yr = cycle.at(data::Channel::rotor_c, grid);
    if (!std::isnan(ys)) cost += (model.stator_sensor(x) - ys) * (model.stator_sensor(x) - ys);
    if (!std::isnan(yr)) cost += (model.rotor_sensor(x) - yr) * (model.rotor_sensor(x) - yr);
  }, o, steps);
  return cost;
}

model::InitialOffsets<double> offsets_by_ceres(const Model<double>& model, const ParamVector<double>& params,
                                        const data::Cycle& cycle) {
  const std::size_t steps = static_cast<std::size_t>(600.0 / cycle.dt_s);
  std::size_t measured = 0;
  for (std::size_t k = 1; k < std::min(steps, cycle.steps); ++k)
    measured += static_cast<std::size_t>(!std::isnan(cycle.at(data::Channel::stator_winding_c, k))) +
                static_cast<std::size_t>(!std::isnan(cycle.at(data::Channel::rotor_c, k)));
  auto* cost = new ceres::DynamicAutoDiffCostFunction<OffsetResiduals, 2>(
      new OffsetResiduals{model, params, cycle, steps});
  cost->AddParameterBlock(2);
  cost->SetNumResiduals(static_cast<int>(measured));
  double o[2] = {0, 0};
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, o);
  for (int j = 0; j < 2; ++j) {
    problem.SetParameterLowerBound(o, j, -model::kInitialOffsetBoundK);
    problem.SetParameterUpperBound(o, j, model::kInitialOffsetBoundK);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-16;
  options.max_num_iterations = 200;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return {o[0], o[1]};
}

// The closed form is the exact minimum; an iterative solver stops near it. So: never a higher
// cost than Ceres reaches with its tolerances at their tightest, and the same point to that
// solver's precision, on the truth and on a starting guess 18 K off (where the offsets are large).
TEST(InitialOffsets, ClosedFormIsTheMinimumTheIterativeSolverApproaches) {
  const testing::Dump& f = generated();
  const Model<double> model = f.motor.model();
  double worst = 0, largest = 0, worst_excess = -1;
  for (const ParamVector<double>& params : {gen::true_parameters(), f.motor.initial_values()}) {
    for (const data::Cycle& cycle : f.dataset.cycles) {
      const model::InitialOffsets<double> closed = model::estimate_initial_offsets(model, params, cycle);
      const model::InitialOffsets<double> ceres = offsets_by_ceres(model, params, cycle);
      worst = std::max({worst, std::abs(closed.stator_core - ceres.stator_core), std::abs(closed.rotor_core - ceres.rotor_core)});
      largest = std::max({largest, std::abs(closed.stator_core), std::abs(closed.rotor_core)});
      const double c = window_cost(model, params, cycle, closed), i = window_cost(model, params, cycle, ceres);
      worst_excess = std::max(worst_excess, (c - i) / i);
      EXPECT_LE(c, i * (1 + 1e-12)) << cycle.name;
    }
  }
  std::printf("closed form vs Ceres over 18 cycle fits: largest offset %.3f K, worst difference %.2e K, "
              "closed form's cost minus Ceres' at most %.1e of it\n", largest, worst, worst_excess);
  EXPECT_GT(largest, 1.0) << "offsets that matter";
  EXPECT_LT(worst, 1e-6);
}

// A bound that holds: a cycle whose first reading is far off its true start makes the unbounded
// offset exceed the bound, and the estimate must then be the bounded minimum, not the clamp of the
// unbounded one (both offsets pull on the same residuals).
TEST(InitialOffsets, AtTheBoundItIsTheBoundedMinimum) {
  const testing::Dump& f = generated();
  data::Cycle cycle = f.dataset.cycles[0];
  for (std::size_t k = 0; k < cycle.steps; ++k) {  // every temperature reading 60 K higher after the first
    float* s = &cycle.samples[data::index_of(data::Channel::stator_winding_c)][k];
    if (k > 0 && !std::isnan(*s)) *s += 60.0f;
  }
  const Model<double> model = f.motor.model();
  const ParamVector<double> truth = gen::true_parameters();
  const model::InitialOffsets<double> closed = model::estimate_initial_offsets(model, truth, cycle);
  const model::InitialOffsets<double> ceres = offsets_by_ceres(model, truth, cycle);
  EXPECT_NEAR(std::max(std::abs(closed.stator_core), std::abs(closed.rotor_core)), model::kInitialOffsetBoundK, 1e-12);
  const double c = window_cost(model, truth, cycle, closed), i = window_cost(model, truth, cycle, ceres);
  std::printf("at the bound: closed form (%.6f, %.6f) K, cost %.9g; Ceres (%.6f, %.6f) K, cost %.9g\n", closed.stator_core,
              closed.rotor_core, c, ceres.stator_core, ceres.rotor_core, i);
  EXPECT_LE(c, i * (1 + 1e-12));
  EXPECT_NEAR(closed.stator_core, ceres.stator_core, 1e-6);
  EXPECT_NEAR(closed.rotor_core, ceres.rotor_core, 1e-3);  // Ceres' bounded steps crawl along the edge
}

TEST(Split, SeededFractionIsRepeatableAndNamedCyclesAreHonoured) {
  const testing::Dump& f = generated();
  const calibrate::Split a = calibrate::split_cycles(f.dataset, {}, 1.0 / 3.0, 5), b = calibrate::split_cycles(f.dataset, {}, 1.0 / 3.0, 5);
  EXPECT_EQ(a.test, b.test);
  const calibrate::Split named = calibrate::split_cycles(f.dataset, {f.dataset.cycles[2].name}, 0, 0);
  ASSERT_EQ(named.test.size(), 1u);
  EXPECT_EQ(named.test[0], 2u);
  EXPECT_EQ(named.train.size(), 8u);
  EXPECT_THROW(calibrate::split_cycles(f.dataset, {"no-such-cycle"}, 0, 0), hostio::BadInput);
}

}  // namespace
}  // namespace lptn::lm
