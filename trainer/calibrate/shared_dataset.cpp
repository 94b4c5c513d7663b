#include "trainer/calibrate/shared_dataset.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "hostio/sha256.hpp"
#include "trainer/calibrate/grid_residuals.hpp"

namespace lptn::calibrate {

SharedDataset join_units(std::size_t units, std::vector<LoadedUnit> mine, const hostio::ProcessGroup& group,
                         std::vector<std::size_t>* unit_of_cycle) {
  // This rank's cycles, each with its share (residual count, file hash), and what the other ranks
  // learn of each (doubles survive JSON exactly).
  std::vector<std::vector<std::pair<data::Cycle, CycleShare>>> per_unit(units);
  std::vector<bool> local(units, false);
  SharedDataset out;
  nlohmann::json stubs = nlohmann::json::array();
  std::map<std::string, std::string> hashes;  // of this rank's files, each taken once
  for (LoadedUnit& u : mine) {
    if (owner_of_unit(u.unit, group) != group.rank())
      throw std::logic_error("join_units: unit " + std::to_string(u.unit) + " is not this rank's");
    local[u.unit] = true;
    for (data::Cycle& c : u.data.cycles) {
      const std::string file = c.file.string();
      if (!hashes.count(file)) hashes[file] = hostio::sha256_file(c.file);
      CycleShare share;
      share.residuals = count_grid_residuals(c);
      share.file_sha256 = hashes[file];
      stubs.push_back({{"unit", u.unit}, {"name", c.name}, {"file", file}, {"t0", c.t0_s}, {"dt", c.dt_s},
                       {"steps", c.steps}, {"residuals", share.residuals}, {"sha256", share.file_sha256},
                       {"map_file", c.map_file.string()}, {"map_sha256", c.map_sha256}});
      per_unit[u.unit].emplace_back(std::move(c), std::move(share));
    }
    for (data::CycleReport& r : u.data.reports) out.data.reports.push_back(std::move(r));
  }
  for (const std::string& text : group.gather(stubs.dump())) {
    for (const nlohmann::json& s : nlohmann::json::parse(text)) {
      const auto unit = s.at("unit").get<std::size_t>();
      if (unit >= units) throw std::logic_error("join_units: a rank sent unit " + std::to_string(unit));
      if (local[unit]) continue;
      data::Cycle c;
      c.name = s.at("name").get<std::string>();
      c.file = s.at("file").get<std::string>();
      c.t0_s = s.at("t0").get<double>();
      c.dt_s = s.at("dt").get<double>();
      c.steps = s.at("steps").get<std::size_t>();
      c.map_file = s.at("map_file").get<std::string>();
      c.map_sha256 = s.at("map_sha256").get<std::string>();
      CycleShare share;
      share.remote = true;
      share.residuals = s.at("residuals").get<std::size_t>();
      share.file_sha256 = s.at("sha256").get<std::string>();
      per_unit[unit].emplace_back(std::move(c), std::move(share));
    }
  }
  if (unit_of_cycle != nullptr) unit_of_cycle->clear();
  for (std::size_t u = 0; u < units; ++u)
    for (auto& [c, share] : per_unit[u]) {
      out.data.cycles.push_back(std::move(c));
      if (group.shared()) out.shares.push_back(std::move(share));
      if (unit_of_cycle != nullptr) unit_of_cycle->push_back(u);
    }
  return out;
}

namespace {

// A cycle's samples as bytes: a JSON header (name, steps, which channels are present) and those
// channels' floats as they lie in memory (both ranks are one build on one kind of machine).
std::string pack(const data::Cycle& c) {
  nlohmann::json present = nlohmann::json::array();
  for (const auto& channel : c.samples) present.push_back(!channel.empty());
  const std::string header = nlohmann::json{{"name", c.name}, {"steps", c.steps}, {"present", present}}.dump();
  std::string bytes = std::to_string(header.size()) + "\n" + header;
  for (const auto& channel : c.samples)
    bytes.append(reinterpret_cast<const char*>(channel.data()), channel.size() * sizeof(float));
  return bytes;
}

void unpack(const std::string& bytes, data::Cycle& c) {
  const std::size_t newline = bytes.find('\n');
  const std::size_t length = std::stoul(bytes.substr(0, newline));
  const nlohmann::json header = nlohmann::json::parse(bytes.substr(newline + 1, length));
  if (header.at("name").get<std::string>() != c.name || header.at("steps").get<std::size_t>() != c.steps)
    throw std::logic_error("balance_training: received " + header.at("name").get<std::string>() + " for " + c.name);
  std::size_t at = newline + 1 + length;
  for (std::size_t ch = 0; ch < c.samples.size(); ++ch) {
    c.samples[ch].clear();
    if (!header.at("present").at(ch).get<bool>()) continue;
    c.samples[ch].resize(c.steps);
    std::copy_n(bytes.data() + at, c.steps * sizeof(float), reinterpret_cast<char*>(c.samples[ch].data()));
    at += c.steps * sizeof(float);
  }
}

}  // namespace

void balance_training(SharedDataset& dataset, const std::vector<std::size_t>& train, const hostio::ProcessGroup& group) {
  if (!group.shared() || !dataset.shared()) return;
  const DatasetRef held_here(dataset);
  // Who holds each cycle, from each rank's list of its own.
  std::string mine;
  for (std::size_t i = 0; i < dataset.data.cycles.size(); ++i)
    if (!held_here.remote(i)) mine += std::to_string(i) + " ";
  std::vector<int> holder(dataset.data.cycles.size(), -1);
  const std::vector<std::string> held = group.gather(mine);
  for (int r = 0; r < group.size(); ++r) {
    std::size_t at = 0;
    const std::string& list = held[static_cast<std::size_t>(r)];
    while (at < list.size()) {
      const std::size_t space = list.find(' ', at);
      holder[std::stoul(list.substr(at, space - at))] = r;
      at = space + 1;
    }
  }
  // The plan: residual counts are known on every rank (remote cycles carry theirs).
  std::vector<double> load(static_cast<std::size_t>(group.size()), 0.0);
  std::vector<std::pair<double, std::size_t>> weight;  // (residuals, cycle), in the split's order on every rank
  for (std::size_t c : train) {
    const auto w = static_cast<double>(held_here.residuals(c));
    load[static_cast<std::size_t>(holder[c])] += w;
    weight.emplace_back(w, c);
  }
  struct Move {
    std::size_t cycle;
    int from, to;
  };
  std::vector<Move> moves;
  for (;;) {
    const auto most = static_cast<int>(std::max_element(load.begin(), load.end()) - load.begin());
    const auto least = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    const double gap = load[static_cast<std::size_t>(most)] - load[static_cast<std::size_t>(least)];
    // The most loaded rank's cycle that best halves the gap (moving w leaves |gap - 2w|; any w in
    // (0, gap) lowers the sum of squared loads, so the plan ends).
    auto pick = weight.end();
    for (auto w = weight.begin(); w != weight.end(); ++w)
      if (holder[w->second] == most && w->first > 0 && w->first < gap &&
          (pick == weight.end() || std::abs(gap - 2 * w->first) < std::abs(gap - 2 * pick->first)))
        pick = w;
    if (pick == weight.end() || moves.size() >= train.size()) break;
    moves.push_back({pick->second, most, least});
    holder[pick->second] = least;
    load[static_cast<std::size_t>(most)] -= pick->first;
    load[static_cast<std::size_t>(least)] += pick->first;
  }
  // Every rank walks the moves in the same order: the earliest unfinished one always has both of
  // its ranks at it, so blocking sends cannot wait on each other in a ring.
  for (const Move& m : moves) {
    data::Cycle& c = dataset.data.cycles[m.cycle];
    CycleShare& share = dataset.shares[m.cycle];
    if (group.rank() == m.from) {
      share.residuals = count_grid_residuals(c);
      group.send(m.to, pack(c));
      for (auto& channel : c.samples) std::vector<float>().swap(channel);
      share.remote = true;
    } else if (group.rank() == m.to) {
      unpack(group.receive(m.from), c);
      share.remote = false;
    }
  }
}

SharedDataset share_work(data::Dataset dataset, const hostio::ProcessGroup& group) {
  SharedDataset out;
  out.data = std::move(dataset);
  if (!group.shared()) return out;
  for (std::size_t i = 0; i < out.data.cycles.size(); ++i) {
    CycleShare share;
    share.residuals = count_grid_residuals(out.data.cycles[i]);
    share.remote = owner_of_unit(i, group) != group.rank();  // its samples stay: only the shared computations leave it to its rank
    out.shares.push_back(std::move(share));
  }
  return out;
}

SharedDataset load_shared_dump(const std::vector<std::filesystem::path>& paths, const hostio::ProcessGroup& group,
                               const data::LoadOptions& options) {
  if (!group.shared()) return {data::load_fleet_dump(paths, options), {}, {}};
  const std::vector<std::filesystem::path> files = data::cycle_files(paths);
  std::vector<std::filesystem::path> own;
  for (std::size_t f = 0; f < files.size(); ++f)
    if (owner_of_unit(f, group) == group.rank()) own.push_back(files[f]);
  // This rank's files on its cores, then back to their units: a file's cycles name it.
  data::Dataset loaded = own.empty() ? data::Dataset{} : data::load_fleet_dump(own, options);
  std::vector<LoadedUnit> mine;
  for (std::size_t f = 0; f < files.size(); ++f) {
    if (owner_of_unit(f, group) != group.rank()) continue;
    LoadedUnit u;
    u.unit = f;
    for (data::Cycle& c : loaded.cycles)
      if (c.file == files[f]) u.data.cycles.push_back(std::move(c));
    for (data::CycleReport& r : loaded.reports)
      if (r.file == files[f]) u.data.reports.push_back(std::move(r));
    mine.push_back(std::move(u));
  }
  return join_units(files.size(), std::move(mine), group);
}

}  // namespace lptn::calibrate
