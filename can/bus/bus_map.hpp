// A converter's bus map (bus.toml) with the converter's DBC it names, read at run time for `lptn
// replay --bus`, `lptn convert --bus` and `lptn vcan-bench --bus`, and at build time by the glue
// generator (can/codegen's lptn-bus-codegen, -DLPTN_BUS), which writes a decoder from this reading:
// no DBC parsing on the target. One reader, one vocabulary (bus_vocabulary.hpp); tests/bus holds the
// decoder and the generated glue equal on one log.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hostio/bad_input.hpp"
#include "lptn/firmware/bus_decoder.hpp"
#include "can/dbc/dbc.hpp"

namespace lptn::bus {

// Bad input: "FILE:LINE: reason", naming the map's table and key.
class MapError : public hostio::BadInput {
 public:
  using BadInput::BadInput;
};

struct MappedInput {
  fw::Input input;
  std::string column;          // its fleet-dump column
  const lptn::dbc::Signal* signal;   // in its message
  double scale = 1, offset = 0;  // input = physical * scale + offset
};

struct MappedMessage {
  const lptn::dbc::Message* message;
  std::vector<MappedInput> inputs;
  const lptn::dbc::Signal* counter = nullptr;  // alive counter, if the map names one
  unsigned max_delta_counter = 0;        // lost frames tolerated + 1
  const lptn::dbc::Signal* crc = nullptr;      // CRC-8 (lptn/firmware/e2e.hpp), if the map names one
  int crc_byte = 0;
  std::uint16_t data_id = 0;
  std::uint32_t cycle_ms = 0;
  fw::InputMask carried = 0;
};

class BusMap {
 public:
  // Throws MapError (the map) or lptn::dbc::Error (its DBC). [outputs] moves the estimator's frames
  // from lptn.dbc's ids (fw::kOutputFrames).
  static std::unique_ptr<BusMap> read(const std::filesystem::path& map_file);
  // The same with the estimator's frames' default ids given, in kOutputFrameNames' order.
  static std::unique_ptr<BusMap> read(const std::filesystem::path& map_file,
                                      const std::array<fw::OutputId, fw::kMaxOutputFrames>& default_outputs);

  // Points into this map: keep the map alive while the estimator runs.
  fw::BusDecoder decoder() const;

  const std::filesystem::path& file() const { return file_; }
  const lptn::dbc::Database& database() const { return dbc_; }
  const std::vector<MappedMessage>& messages() const { return messages_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  // The CAN ids of the estimator's frames on this bus ([outputs]; lptn.dbc's by default), in
  // fw::kOutputFrames' order.
  const std::array<fw::OutputId, fw::kMaxOutputFrames>& output_ids() const { return outputs_; }

  // The frame a message sends with these input values (by fw::Input; inputs of other multiplexor
  // values are left out), the multiplexor's value `mux` (if it has one), its alive counter and,
  // last, its CRC.
  fw::CanFrame encode(const MappedMessage& m, const double (&values)[fw::kNumInputs], long long mux,
                      std::uint32_t counter) const;
  // The multiplexor values a message must send for every input it maps to go out (one, -1, for
  // a message without multiplexor).
  static std::vector<long long> pages(const MappedMessage& m);

 private:
  static bool decode(const void* self, const fw::CanFrame& f, fw::BusReading& out);

  std::filesystem::path file_;
  lptn::dbc::Database dbc_;
  std::vector<MappedMessage> messages_;
  std::vector<std::string> warnings_;
  std::array<fw::OutputId, fw::kMaxOutputFrames> outputs_{};
};

}  // namespace lptn::bus
