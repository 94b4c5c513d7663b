// Scores parameter sets on training cycles, many at a time, for calibrators that search by
// trying sets (TD3's sequential formulation): each set's pooled RMSE with the unmeasured nodes'
// start offsets re-fitted for it, exactly as the metrics fit them, and features of its residuals
// that say where in the data the model runs hot or cold.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "lptn/model.hpp"
#include "trainer/calibrate/problem.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/simulate.hpp"

namespace lptn::calibrate {

// Splits of the samples (each at the training data's median unless said otherwise). A feature is
// the mean residual where the split holds minus where it does not: a conductance to the cooling
// air shows where the airflow is high, a capacitance where the temperature moves, a loss where
// the current is high.
inline constexpr std::array<std::string_view, 7> kResidualSplits{
    "high_airflow", "high_current", "high_speed", "heating",  // heating: the measurement rising over a minute
    "hot",                                                     // the stator measurement above its median
    "first_10_min",                                            // the cycle's first 600 s (the start offsets' window)
    "warm_ambient"};

struct SetScore {
  double rmse_k = 0;                  // stator and rotor residuals pooled
  double stator_rmse_k = 0, rotor_rmse_k = 0;
  std::vector<float> features;        // SetScorer::features() of them, see there
  std::size_t simulated_steps = 0;    // model steps this score took (offsets' fit included)
};

class SetScorer {
 public:
  // `cycles` are the ones to score on, on the grid they will be simulated on (a coarse grid is the
  // caller's choice: data::coarse_grid). `fixed` holds every parameter that is not free.
  SetScorer(const Model<double>& model, FreeParameters free, const ParamVector<double>& fixed,
            std::vector<data::Cycle> cycles);

  std::size_t parameters() const { return free_.size(); }
  // Per sensor (stator, then rotor; zeros where not measured): ln of the RMSE in K, asinh of the
  // bias / 0.2 K, and asinh of each kResidualSplits difference / 0.2 K (linear below 0.2 K, slowly
  // growing beyond, so that 300 K off and 0.05 K off both read on one scale).
  static constexpr std::size_t kPerSensor = 2 + kResidualSplits.size();
  static constexpr std::size_t features() { return 2 * kPerSensor; }

  // The full parameter vector for normalized free parameters u in [-1, 1]^P (clamped).
  ParamVector<double> params_for(const double* u) const;
  // n sets (row-major n x P normalized) scored on `threads` threads; the result is the same for any
  // number of threads (each cycle's sums in its own slot, added in a fixed order).
  void score(const double* u, std::size_t n, SetScore* out, int threads) const;

  struct Sums;  // one set's residual sums on one cycle

 private:
  // Sets scored side by side on one cycle (lanes.hpp: the model stepped in vector registers),
  // each with a double's bits.
  static constexpr std::size_t kLanes = 4;
  // Scores the `count` (1..kLanes) sets p[0..count) on cycle ci into sums[0..count).
  void score_cycle(const ParamVector<double>* p, std::size_t count, std::size_t ci, Sums* sums) const;

  Model<double> model_;
  FreeParameters free_;
  ParamVector<double> fixed_;
  std::vector<data::Cycle> cycles_;
  std::vector<model::PreparedCycle> prepared_;  // each cycle's inputs, prepared once for every set scored
  std::vector<std::vector<std::uint8_t>> split_bits_;  // per cycle and sample: bit s set where split s holds
};

}  // namespace lptn::calibrate
