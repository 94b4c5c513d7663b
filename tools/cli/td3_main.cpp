// lptn-td3: `lptn calibrate` with the TD3 calibrator (libtorch). lptn runs it for --method td3 and
// td3-episode with the same arguments, so that libtorch is loaded only by the command that uses it.
#include <cstdio>
#include <filesystem>
#include <string>

#include "hostio/progress_line.hpp"
#include "lptn/version.hpp"
#include "tools/cli/commands.hpp"
#include "trainer/td3/td3_calibration.hpp"
#include "trainer/td3/td3_settings.hpp"

namespace lptn::cli {
namespace {

void run_td3(const CalibrateArgs& a, const MotorFile& motor, const data::Dataset& dataset, const Split& split,
             CalibrationResult& r) {
  const td3::Formulation formulation = a.method == "td3" ? td3::Formulation::per_step : td3::Formulation::episode;
  td3::TrainingSettings settings = td3::default_settings(formulation);
  try {
    if (!a.config.empty()) settings = td3::load_settings(a.config, formulation);
  } catch (const td3::SettingsError& e) {
    throw BadInput(e.what());
  }
  if (a.config.empty() || a.seed_given) settings.seed = settings.agent.seed = a.seed;  // --seed wins over the file
  if (a.episodes > 0) settings.max_episodes = a.episodes;
  bool rotor = false;
  for (std::size_t c : split.train) rotor = rotor || dataset.cycles[c].has(data::Channel::rotor_c);
  if (!rotor) settings.reward.w3 = 0.0;  // eq. 15 without the rotor term where the rotor is not measured
  const std::filesystem::path checkpoints = a.checkpoint_dir.empty() ? std::filesystem::path(a.out + ".checkpoints") : std::filesystem::path(a.checkpoint_dir);
  ProgressLine line(a.quiet);
  const td3::Td3Outcome o = td3::train_td3(motor, dataset, split.train, settings, checkpoints, a.resume,
                                           [&](const td3::EpisodeReport& e) {
                                             char buf[200];
                                             std::snprintf(buf, sizeof buf, "%s: episode %4d/%d %s reward %7.3f  average %7.3f  %s elapsed, ~%s left%s",
                                                           td3::to_string(formulation), e.episode, e.max_episodes,
                                                           ProgressLine::bar(double(e.episode) / e.max_episodes).c_str(),
                                                           e.reward, e.average, ProgressLine::clock(e.seconds).c_str(),
                                                           ProgressLine::clock(e.seconds_left).c_str(), e.random ? " (random actions)" : "");
                                             line.update(buf, e.episode == e.max_episodes);
                                             return true;
                                           });
  line.finish();
  for (int i = 0; i < kNumParams; ++i) r.parameters[static_cast<std::size_t>(i)].value = o.values[i];
  r.method = td3::to_string(formulation);
  r.settings = td3::to_json(settings);
  nlohmann::json curve = nlohmann::json::array();
  for (const td3::EpisodeRecord& e : o.curve) curve.push_back(td3::to_json(e));
  r.details = {{"episodes", o.episodes},
               {"initial_evaluation", o.initial_evaluation},
               {"reached_target", o.reached_target},
               {"resumed_from_episode", o.resumed_from},
               {"checkpoints", checkpoints.string()},
               {"constant_set", "policy over the training data's operating points, tanh outputs averaged, mapped onto the bounds; "
                                "of the checkpoints' sets the one with the lowest training RMSE (episode 0: the starting guess)"},
               {"best_episode", o.best_episode},
               {"best_train_rmse_k", o.best_train_rmse_k},
               {"training_curve", curve}};
  r.seconds = o.seconds;
  r.has_actor = true;
  ActorExport& x = r.actor;
  x.obs_offset = {0.0, 0.0};
  x.obs_scale = o.obs_scale;
  x.layers = {{o.actor.inputs, o.actor.hidden, o.actor.w1, o.actor.b1},
              {o.actor.hidden, o.actor.hidden, o.actor.w2, o.actor.b2},
              {o.actor.hidden, o.actor.outputs, o.actor.w3, o.actor.b3}};
  x.param_indices = o.param_indices;
  x.check_obs = o.check_obs;
  x.check_actions = o.check_actions;
}

}  // namespace
}  // namespace lptn::cli

int main(int argc, char** argv) {
  CLI::App app{"lptn-td3: lptn calibrate with the TD3 calibrator (lptn runs it for --method td3|td3-episode)", "lptn-td3"};
  app.require_subcommand(1);
  app.set_version_flag("--version", lptn::kNameAndVersion);
  lptn::cli::add_calibrate(app, &lptn::cli::run_td3);
  return lptn::cli::run_cli(app, argc, argv);
}
