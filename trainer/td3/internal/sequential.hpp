// The sequential formulation (`--method td3`): train_td3 runs this for Formulation::sequential.
#pragma once

#include "trainer/td3/td3_calibration.hpp"

namespace lptn::td3 {

Td3Outcome train_sequential(const model::MotorFile& motor, const data::Dataset& dataset, const std::vector<std::size_t>& train,
                            const TrainingSettings& settings, const std::filesystem::path& checkpoint_dir, bool resume,
                            const Td3Progress& progress, const WarmStart& warm);

}  // namespace lptn::td3
