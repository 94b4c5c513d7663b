#include "trainer/lm/lm_result.hpp"

#include <cstdio>
#include <utility>

#include "hostio/progress_line.hpp"

namespace lptn::lm {

nlohmann::json to_json(const LmSettings& s) {
  return {{"max_iterations", s.max_iterations}, {"function_tolerance", s.function_tolerance},
          {"parameter_tolerance", s.parameter_tolerance}, {"threads", s.threads},
          {"correlation_flag", s.correlation_flag}, {"judge_identifiability", s.judge_identifiability},
          {"max_log_std", s.max_log_std}, {"initial_offsets", "estimated per cycle (stator core, rotor core)"}};
}

void mark_not_identifiable(calibrate::CalibrationResult& r, const std::vector<NotIdentifiable>& parameters) {
  for (const NotIdentifiable& n : parameters) {
    calibrate::ParameterResult& p = r.parameters[static_cast<std::size_t>(n.index)];
    p.calibrated = false;
    p.identifiable = false;
    p.identifiability = n.reason;
  }
}

void record_lm_fit(calibrate::CalibrationResult& r, const LmReport& fit, const calibrate::FreeParameters& given,
                   const std::vector<std::string>& fitted, nlohmann::json settings) {
  // The parameters the last fit moved: the given ones but those it found it could not pin (the
  // order of its at_bound flags and correlation matrix).
  calibrate::FreeParameters free;
  for (std::size_t j = 0; j < given.size(); ++j) {
    bool dropped = false;
    for (const NotIdentifiable& n : fit.not_identifiable) dropped = dropped || n.index == given.index[j];
    if (dropped) continue;
    free.index.push_back(given.index[j]);
    free.min.push_back(given.min[j]);
    free.max.push_back(given.max[j]);
    free.log_scale.push_back(given.log_scale[j]);
  }
  for (int i = 0; i < kNumParams; ++i) {
    r.parameters[static_cast<std::size_t>(i)].value = fit.values[i];
    r.parameters[static_cast<std::size_t>(i)].std_error = fit.std_error[i];
  }
  mark_not_identifiable(r, fit.not_identifiable);
  r.correlated = fit.correlated;
  r.method = "lm";
  r.has_actor = false;  // a TD3 actor belongs to the model it was trained for
  r.settings = std::move(settings);
  nlohmann::json offsets = nlohmann::json::array();
  for (std::size_t i = 0; i < fitted.size() && i < fit.offsets.size(); ++i)
    offsets.push_back({{"cycle", fitted[i]},
                       {"stator_core_k", fit.offsets[i].stator_core},
                       {"rotor_core_k", fit.offsets[i].rotor_core}});
  nlohmann::json at_bound = nlohmann::json::array();
  for (std::size_t j = 0; j < free.size() && j < fit.at_bound.size(); ++j)
    if (fit.at_bound[j]) at_bound.push_back(std::string(param_spec(free.index[j]).name));
  nlohmann::json names = nlohmann::json::array();
  for (int i : free.index) names.push_back(std::string(param_spec(i).name));
  r.details = {{"iterations", fit.iterations},   {"converged", fit.converged},
               {"termination", fit.termination}, {"initial_cost_k2", fit.initial_cost},
               {"final_cost_k2", fit.final_cost}, {"residuals", fit.residuals},
               {"rmse_k", fit.rmse_k},           {"correlation_time", fit.correlation_time},
               {"at_bound", at_bound},           {"correlation", {{"parameters", names}, {"matrix", fit.correlation}}},
               {"initial_offsets", offsets},     {"mpi_ranks", fit.mpi_ranks},
               {"rank_residuals", fit.rank_residuals},
               {"evaluations", fit.evaluations},  {"joined_doubles", fit.joined_doubles},
               {"join_seconds", fit.join_seconds}, {"linear_solver_seconds", fit.linear_solver_seconds}};
  r.seconds = fit.seconds;
}

void calibrate_lm(const calibrate::CalibrationRequest& /*request*/, const MotorFile& motor, calibrate::DatasetRef dataset,
                  const calibrate::Split& split, calibrate::CalibrationResult& result, const calibrate::CalibrationProgress& progress) {
  LmSettings settings;
  settings.judge_identifiability = true;  // what the data cannot pin stays the motor file's, said so
  const LmReport fit = fit_lm(motor, motor.initial_values(), dataset, split.train, settings,
                              [&](int iteration, double rmse, double seconds) {
                                if (!progress) return;
                                char buf[160];
                                std::snprintf(buf, sizeof buf, "lm: iteration %3d  rmse %8.4f K  %s", iteration, rmse,
                                              hostio::ProgressLine::clock(seconds).c_str());
                                progress(buf, true);
                              });
  record_lm_fit(result, fit, calibrate::FreeParameters::from_motor(motor), result.train_cycles, to_json(settings));
}

}  // namespace lptn::lm
