#include "trainer/td3/internal/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "hostio/atomic_file.hpp"

namespace lptn::td3 {

namespace {
const char* kStateFile = "state.json";
}

std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const Agent& agent, int episode,
                                       const nlohmann::json& identity, nlohmann::json state) {
  std::filesystem::create_directories(dir);
  char name[32];
  std::snprintf(name, sizeof name, "agent-%06d.bin", episode);
  agent.save(dir / name);
  state["identity"] = identity;
  state["episode"] = episode;
  state["agent_file"] = name;
  hostio::write_file_atomically(dir / kStateFile, state.dump() + "\n");
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string f = entry.path().filename().string();
    if (f.rfind("agent-", 0) == 0 && f != name) std::filesystem::remove(entry.path());
  }
  return dir / name;
}

nlohmann::json read_checkpoint(const std::filesystem::path& dir, const nlohmann::json& identity, Agent& agent) {
  const std::filesystem::path file = dir / kStateFile;
  std::ifstream in(file);
  if (!in) throw std::runtime_error("--resume: no checkpoint at " + file.string());
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": unreadable checkpoint (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("identity") || j.at("identity") != identity)
    throw std::runtime_error("--resume: the checkpoint in " + dir.string() +
                             " was made with other settings, data or parameters; start afresh without --resume");
  agent.load(dir / j.at("agent_file").get<std::string>());
  return j;
}

std::string to_text(const std::mt19937_64& rng) {
  std::ostringstream s;
  s << rng;
  return s.str();
}

void from_text(const std::string& text, std::mt19937_64& rng) {
  std::istringstream s(text);
  s >> rng;
  if (!s) throw std::runtime_error("checkpoint: unreadable generator state");
}

nlohmann::json run_state_json(const RunState& s, const char* best_at_key) {
  nlohmann::json j;
  j["rng"] = to_text(s.rng);
  j["seconds"] = s.seconds;
  j["initial_evaluation"] = s.initial_evaluation;
  j["best"] = std::vector<double>(s.best.begin(), s.best.end());
  j["best_train_rmse_k"] = s.best_train_rmse_k;
  j[best_at_key] = s.best_at;
  j["simulated_steps"] = s.simulated_steps;
  j["updates"] = s.updates;
  j["curve"] = nlohmann::json::array();
  for (const EpisodeRecord& r : s.curve) j["curve"].push_back(to_json(r));
  return j;
}

void read_run_state(const nlohmann::json& j, const char* best_at_key, RunState& s) {
  s.done = j.at("episode").get<int>();
  from_text(j.at("rng").get<std::string>(), s.rng);
  s.seconds = j.at("seconds").get<double>();
  s.initial_evaluation = j.at("initial_evaluation").get<double>();
  const auto best = j.at("best").get<std::vector<double>>();
  std::copy(best.begin(), best.end(), s.best.begin());
  s.best_train_rmse_k = j.at("best_train_rmse_k").get<double>();
  s.best_at = j.at(best_at_key).get<int>();
  s.simulated_steps = j.at("simulated_steps").get<std::size_t>();
  s.updates = j.at("updates").get<long long>();
  s.curve.clear();
  for (const auto& r : j.value("curve", nlohmann::json::array())) s.curve.push_back(record_from_json(r));
}

}  // namespace lptn::td3
