// The estimator's output frames with lptn.dbc's CAN ids: what a bus map's [outputs] moves. Apart
// from output_frames.hpp because the bus-map reader (can/bus) needs the ids but not the compiled-in
// bus glue, which the build generates with that reader.
#pragma once

#include "lptn/can/lptn_frames.hpp"
#include "lptn/firmware/bus_decoder.hpp"

namespace lptn::fw {

// The frames in the order pack_outputs fills them, with lptn.dbc's ids. can/bus/bus_vocabulary.hpp
// lists the same names for the maps' [outputs]; output_frames.hpp holds the two lists equal.
struct OutputFrame {
  const char* name;
  OutputId dbc;
};
inline constexpr OutputFrame kOutputFrames[kMaxOutputFrames] = {
    {can::LptnTemperatures::kName, {can::LptnTemperatures::kId, can::LptnTemperatures::kExtended}},
    {can::LptnTemperatureStd::kName, {can::LptnTemperatureStd::kId, can::LptnTemperatureStd::kExtended}},
    {can::LptnMargin::kName, {can::LptnMargin::kId, can::LptnMargin::kExtended}},
    {can::LptnStatus::kName, {can::LptnStatus::kId, can::LptnStatus::kExtended}},
    {can::LptnInnovation::kName, {can::LptnInnovation::kId, can::LptnInnovation::kExtended}},
    {can::LptnCooling::kName, {can::LptnCooling::kId, can::LptnCooling::kExtended}},
};

}  // namespace lptn::fw
