// Calibration by search alone, without learning: the baselines the calibration benchmark sets
// beside TD3 at the same simulation budget, to show what the learning adds. Both score sets as
// TD3's sequential formulation does (SetScorer on the coarse training grid, start offsets re-fitted
// per set) and re-score their best on the data's own grid as the metrics score it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "hostio/worker_threads.hpp"
#include "trainer/calibrate/calibration_request.hpp"
#include "trainer/calibrate/problem.hpp"

namespace lptn::search {

enum class SearchMethod {
  random,  // `--method random-search`: sets drawn uniformly around the guess (as TD3's episodes start)
  cma_es,  // `--method cma-es`: CMA-ES from the guess (Hansen's tutorial, its defaults)
};

struct SearchSettings {
  // Model steps (coarse grid, offsets' fits and the final re-scores included), as TD3 reports
  // them: 1.8e9 is about what `--method td3` simulates with its defaults on the benchmark's dump.
  std::size_t budget_steps = 1'800'000'000;
  int coarse_factor = 10;
  double start_spread = 0.5;  // random search: guess +- this, normalized units (TD3's start_spread)
  double sigma = 0.25;        // CMA-ES: the first step size, normalized units
  int population = 0;         // CMA-ES: lambda (0: 4 + 3 ln n)
  std::uint64_t seed = 1;
  int threads = hostio::worker_threads();
};
nlohmann::json to_json(const SearchSettings& settings);
const char* to_string(SearchMethod method);  // the --method name

struct SearchOutcome {
  ParamVector<double> values{};
  double best_train_rmse_k = 0;  // on the data's grid, stator and rotor pooled (as the metrics)
  std::size_t simulated_steps = 0;
  std::size_t evaluations = 0;   // sets scored on the coarse grid
  double seconds = 0;
};

// Called after every batch of sets: steps so far, the budget, the best coarse RMSE so far.
using SearchProgress = std::function<void(std::size_t steps, std::size_t budget, double best_rmse_k, double seconds)>;

SearchOutcome search_calibration(SearchMethod method, const MotorFile& motor, const data::Dataset& dataset,
                                 const std::vector<std::size_t>& train, const SearchSettings& settings,
                                 const SearchProgress& progress = {});

// `--method random-search` and `--method cma-es` (a CalibrationMethod): search_calibration with
// the request's seed and budget, its best set and its details into `result`. Progress: the model
// steps spent against the budget, the best RMSE so far.
void calibrate_by_search(const calibrate::CalibrationRequest& request, const MotorFile& motor, calibrate::DatasetRef dataset,
                         const calibrate::Split& split, calibrate::CalibrationResult& result, const calibrate::CalibrationProgress& progress);

}  // namespace lptn::search
