// BusMap::read() with the estimator's frames at lptn.dbc's ids, as compiled in (fw::kOutputFrames).
#include "can/bus/bus_map.hpp"
#include "lptn/firmware/output_ids.hpp"

namespace lptn::bus {

std::unique_ptr<BusMap> BusMap::read(const std::filesystem::path& map_file) {
  std::array<fw::OutputId, fw::kMaxOutputFrames> ids{};
  for (int k = 0; k < fw::kMaxOutputFrames; ++k) ids[static_cast<std::size_t>(k)] = fw::kOutputFrames[k].dbc;
  return read(map_file, ids);
}

}  // namespace lptn::bus
