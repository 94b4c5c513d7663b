#include "trainer/search/search.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "hostio/progress_line.hpp"
#include "trainer/calibrate/set_scorer.hpp"
#include "trainer/data/coarse_grid.hpp"
#include "trainer/search/internal/cma_es.hpp"

namespace lptn::search {

const char* to_string(SearchMethod m) { return m == SearchMethod::random ? "random-search" : "cma-es"; }

nlohmann::json to_json(const SearchSettings& s) {
  return {{"budget_steps", s.budget_steps}, {"coarse_factor", s.coarse_factor}, {"start_spread", s.start_spread},
          {"sigma", s.sigma}, {"population", s.population}, {"seed", s.seed}};
}

SearchOutcome search_calibration(SearchMethod method, const MotorFile& motor, const data::Dataset& dataset,
                                 const std::vector<std::size_t>& train, const SearchSettings& settings,
                                 const SearchProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const calibrate::FreeParameters free = calibrate::FreeParameters::from_motor(motor);
  const std::size_t p = free.size();
  if (p == 0) throw std::runtime_error("no parameter is marked for calibration in " + motor.path.string());
  std::vector<data::Cycle> coarse;
  for (std::size_t c : train) coarse.push_back(data::coarse_grid(dataset.cycles[c], settings.coarse_factor));
  const Model<double> model = motor.model();
  const calibrate::SetScorer scorer(model, free, motor.initial_values(), std::move(coarse));
  std::vector<double> guess;
  const ParamVector<double> start = motor.initial_values();
  for (std::size_t j = 0; j < p; ++j) guess.push_back(to_normalized(start[free.index[j]], free.min[j], free.max[j]));

  SearchOutcome out;
  std::vector<std::pair<double, std::vector<double>>> best;  // the three best sets scored, by coarse RMSE
  auto score = [&](const std::vector<double>& u, std::size_t n) {
    std::vector<double> clamped(u);
    for (double& x : clamped) x = std::clamp(x, -1.0, 1.0);
    std::vector<calibrate::SetScore> s(n);
    scorer.score(clamped.data(), n, s.data(), settings.threads);
    std::vector<double> rmse(n);
    for (std::size_t i = 0; i < n; ++i) {
      out.simulated_steps += s[i].simulated_steps;
      ++out.evaluations;
      rmse[i] = s[i].rmse_k;
      best.emplace_back(rmse[i], std::vector<double>(clamped.begin() + static_cast<std::ptrdiff_t>(i * p),
                                                     clamped.begin() + static_cast<std::ptrdiff_t>((i + 1) * p)));
    }
    std::stable_sort(best.begin(), best.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    if (best.size() > 3) best.resize(3);
    if (progress)
      progress(out.simulated_steps, settings.budget_steps, best.front().first,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return rmse;
  };

  if (method == SearchMethod::random) {
    std::mt19937_64 rng(settings.seed ^ 0x4a4d0ffeeULL);
    std::uniform_real_distribution<double> d(-settings.start_spread, settings.start_spread);
    const std::size_t batch = 8;
    while (out.simulated_steps < settings.budget_steps) {
      std::vector<double> u(batch * p);
      for (std::size_t i = 0; i < u.size(); ++i) u[i] = guess[i % p] + d(rng);
      score(u, batch);
    }
  } else {
    search::CmaEs cma(guess, settings.sigma, settings.seed, settings.population);
    while (out.simulated_steps < settings.budget_steps) {
      const std::vector<double> u = cma.ask();
      std::vector<double> cost = score(u, static_cast<std::size_t>(cma.lambda()));
      // Outside the bounds a point is scored where it is clamped to, and pays for the distance,
      // so that the mean is drawn back inside rather than drifting along a bound.
      for (std::size_t i = 0; i < cost.size(); ++i) {
        double outside = 0;
        for (std::size_t j = 0; j < p; ++j) {
          const double x = u[i * p + j];
          outside += (x - std::clamp(x, -1.0, 1.0)) * (x - std::clamp(x, -1.0, 1.0));
        }
        cost[i] = std::log(cost[i]) + 10 * outside;
      }
      cma.tell(cost);
    }
  }
  // The best three on the data's own grid, with the metrics' offsets.
  out.best_train_rmse_k = std::numeric_limits<double>::infinity();
  for (const auto& [rmse, u] : best) {
    const ParamVector<double> set = scorer.params_for(u.data());
    const calibrate::SplitMetrics m = calibrate::evaluate_split(model, set, dataset, train, settings.threads);
    for (std::size_t c : train) out.simulated_steps += calibrate::evaluation_steps(dataset.cycles[c]);
    const double fine = pool({m.stator, m.rotor}).rmse_k;
    if (fine < out.best_train_rmse_k) {
      out.best_train_rmse_k = fine;
      out.values = set;
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void calibrate_by_search(const calibrate::CalibrationRequest& request, const MotorFile& motor, calibrate::DatasetRef dataset,
                         const calibrate::Split& split, calibrate::CalibrationResult& result, const calibrate::CalibrationProgress& progress) {
  const SearchMethod method = request.method == "cma-es" ? SearchMethod::cma_es : SearchMethod::random;
  SearchSettings settings;
  settings.seed = request.seed;
  if (request.budget_steps > 0) settings.budget_steps = request.budget_steps;
  const SearchOutcome o = search_calibration(method, motor, dataset.data, split.train, settings,
                                             [&](std::size_t steps, std::size_t budget, double best, double seconds) {
                                               if (!progress) return;
                                               const double done = std::min(1.0, double(steps) / double(budget));
                                               char buf[200];
                                               std::snprintf(buf, sizeof buf, "%s: %5.1f G of %.1f G model steps %s best %.4f K  %s elapsed",
                                                             to_string(method), double(steps) / 1e9, double(budget) / 1e9,
                                                             hostio::ProgressLine::bar(done).c_str(), best, hostio::ProgressLine::clock(seconds).c_str());
                                               progress(buf, done >= 1.0);
                                             });
  for (int i = 0; i < kNumParams; ++i) result.parameters[static_cast<std::size_t>(i)].value = o.values[i];
  result.method = to_string(method);
  result.settings = to_json(settings);
  result.details = {{"simulated_steps", o.simulated_steps}, {"evaluations", o.evaluations}, {"best_train_rmse_k", o.best_train_rmse_k},
                    {"result", "the best of the three best sets scored on the training grid, re-scored on the data's own grid with the "
                               "metrics' start offsets"}};
  result.seconds = o.seconds;
}

}  // namespace lptn::search
