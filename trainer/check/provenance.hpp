// Whether the data at hand is the data a calibration was fitted on: cycle by cycle, by name and by
// the SHA-256 of its file (calibration.json's data.files[]), and the data's motor constants (its
// motor.toml, where it has one) against the calibration's. A cycle of the same name in another
// file is another drive: it is never called "train" or "test" because of its name.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "trainer/calibrate/calibration_file.hpp"
#include "trainer/data/dataset.hpp"
#include "trainer/model/motor_file.hpp"

namespace lptn::check {

struct CycleProvenance {
  std::string name;
  bool seen = false;  // the calibration read this very file under this name
  std::string role;   // seen: "train", "test" or "" (read but in neither list); else ""
  // not seen: "not among the calibration's cycles", "same name, another file", or "same file, read
  // through another data map"
  std::string why;
  // read through another data map: which the calibration read it through, which this reading,
  // e.g. "the calibration's export/data.toml, this reading's none (lptn's own CSV)"
  std::string maps;
};

struct Provenance {
  std::vector<CycleProvenance> cycles;  // in the dataset's order
  // The data's motor constants that differ from the calibration's, e.g. "pole_pairs 3 (calibration: 2)";
  // empty where they agree or the data has no motor file.
  std::vector<std::string> constants;
  bool all_seen() const;    // every cycle, and no constant differs: the calibration's own data
  std::size_t unseen() const;
  std::vector<std::string> unseen_names() const;
  // What of the data this calibration never saw, e.g. "4 of 4 cycles (the calibration's cycle
  // names, other files)", and constants that differ; "" for the calibration's own data.
  std::string summary() const;
  // Some cycle is the calibration's own file read through another data map than it read it through.
  bool other_map() const;
};

// `data_motor`: the motor file found beside the data (DIR/motor.toml), if any. Hashes the cycles'
// files (each once).
Provenance provenance(const calibrate::CalibrationResult& calibration, const data::Dataset& dataset,
                      const std::optional<MotorFile>& data_motor = std::nullopt);

// The motor file beside a fleet dump directory (DIR/motor.toml), if it is there and reads; the
// data's own description of its motor.
std::optional<MotorFile> motor_beside(const std::vector<std::string>& data_paths);

}  // namespace lptn::check
