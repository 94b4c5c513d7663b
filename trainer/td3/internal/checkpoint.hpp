// A TD3 run's checkpoint, whatever the formulation: the agent file (networks, optimizer, replay
// buffer, its generator) and state.json (the run's own state, with the identity a --resume must
// match). The state file is the commit point: it names the agent file written just before it.
#pragma once

#include <filesystem>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "trainer/td3/internal/run_record.hpp"
#include "trainer/td3/td3_agent.hpp"

namespace lptn::td3 {

// Writes agent-EEEEEE.bin for `episode`, then state.json = `state` with "identity", "episode" and
// "agent_file" added (atomically), then removes older agent files. Returns the agent file.
std::filesystem::path write_checkpoint(const std::filesystem::path& dir, const Agent& agent, int episode,
                                       const nlohmann::json& identity, nlohmann::json state);

// Reads state.json, refuses one made with another identity (std::runtime_error naming the
// directory), loads the agent file it names into `agent`, and returns the state.
nlohmann::json read_checkpoint(const std::filesystem::path& dir, const nlohmann::json& identity, Agent& agent);

std::string to_text(const std::mt19937_64& rng);
void from_text(const std::string& text, std::mt19937_64& rng);

// The run state as state.json holds it. `best_at_key` names the best set's round ("best_round",
// the sequential formulation) or episode ("best_episode"), as their checkpoints always have.
nlohmann::json run_state_json(const RunState& s, const char* best_at_key);
// Back from read_checkpoint()'s state (`done` from its "episode"); a curve may be absent (empty).
void read_run_state(const nlohmann::json& j, const char* best_at_key, RunState& s);

}  // namespace lptn::td3
