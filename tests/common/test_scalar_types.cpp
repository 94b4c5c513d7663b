// One model in float (target), double (trainer) and ceres::Jet (exact derivatives for LM).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>

#include "lptn/model.hpp"
#include "lptn_testing/reference_case.hpp"

namespace lptn {
namespace {

template <class T>
void simulate(const Model<double>& md, const ParamVector<T>& p, T* x, int steps) {
  const Model<double>& model = md;
  model.initial_state(x, T(20.0), T(20.0));
  for (int k = 0; k < steps; ++k) {
    Inputs<double> in = testing::rated_inputs();
    in.current_a = 70.0 + 40.0 * std::sin(0.1 * k / 200.0);
    in.airflow_m3s = (k / 6000) % 2 ? 0.5 : 1.0;
    in.has_torque = (k / 9000) % 2 == 0;
    model.step(x, in, p.data(), 0.1);
  }
}

const EffectSet kAll = (EffectSet{1} << kNumEffects) - 1;

TEST(ScalarTypes, FloatTracksDoubleWithinAFewHundredthsOfAKelvinOverAnHour) {
  const auto m = testing::example_motor();
  const Model<double> md(m, kAll);
  const Model<float> mf(m.cast<float>(), kAll);
  const auto pd = default_params<double>();
  const auto pf = default_params<float>();
  double xd[kMaxStates];
  float xf[kMaxStates];
  md.initial_state(xd, 20.0, 20.0);
  mf.initial_state(xf, 20.f, 20.f);
  double worst = 0;
  for (int k = 0; k < 36000; ++k) {
    Inputs<double> in = testing::rated_inputs();
    in.current_a = 70.0 + 40.0 * std::sin(0.1 * k / 200.0);
    Inputs<float> inf;
    inf.speed_rpm = static_cast<float>(in.speed_rpm);
    inf.torque_nm = static_cast<float>(in.torque_nm);
    inf.current_a = static_cast<float>(in.current_a);
    inf.frequency_hz = static_cast<float>(in.frequency_hz);
    inf.voltage_v = static_cast<float>(in.voltage_v);
    inf.airflow_m3s = static_cast<float>(in.airflow_m3s);
    inf.ambient_c = static_cast<float>(in.ambient_c);
    inf.has_torque = in.has_torque;
    inf.has_voltage = in.has_voltage;
    md.step(xd, in, pd.data(), 0.1);
    mf.step(xf, inf, pf.data(), 0.1f);
    for (int i = 0; i < md.num_states(); ++i) worst = std::max(worst, std::abs(xd[i] - xf[i]));
  }
  EXPECT_LT(worst, 0.05);
  // The winding runs hot (the case exercises the model): over 60 °C in the paper's model alone;
  // with every effect on, the dictionary's three thermal masses (100 W/K to 300 kJ/K each, at their
  // start values) take up part of the heat and it reaches 54 °C after the hour.
  EXPECT_GT(xd[0], 50.0);
}

TEST(ScalarTypes, JetValuesEqualDoubleAndDerivativesMatchFiniteDifferences) {
  using Jet = ceres::Jet<double, kNumParams>;
  const Model<double> model(testing::example_motor(), kAll);
  const auto pd = default_params<double>();
  ParamVector<Jet> pj;
  for (int i = 0; i < kNumParams; ++i) pj[i] = Jet(pd[i], i);
  const int steps = 6000;
  Jet xj[kMaxStates];
  double xd[kMaxStates];
  simulate(model, pj, xj, steps);
  simulate(model, pd, xd, steps);
  for (int i = 0; i < model.num_states(); ++i) EXPECT_NEAR(xj[i].a, xd[i], 1e-10 * std::abs(xd[i]));

  int checked = 0;
  for (int i = 0; i < kNumParams; ++i) {
    auto plus = pd, minus = pd;
    const double h = 1e-6 * std::max(1.0, std::abs(pd[i]));
    plus[i] += h;
    minus[i] -= h;
    double xp[kMaxStates], xm[kMaxStates];
    simulate(model, plus, xp, steps);
    simulate(model, minus, xm, steps);
    for (int s = 0; s < model.num_states(); ++s) {
      const double fd = (xp[s] - xm[s]) / (2 * h);
      EXPECT_NEAR(xj[s].v[i], fd, 1e-5 * std::max(1.0, std::abs(fd))) << param_spec(i).name << " state " << s;
      if (std::abs(fd) > 1e-3) ++checked;
    }
  }
  EXPECT_GT(checked, kNumParams);  // most parameters do move the states
}

}  // namespace
}  // namespace lptn
