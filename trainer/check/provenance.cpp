#include "trainer/check/provenance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <type_traits>

#include "hostio/sha256.hpp"
#include "hostio/worker_threads.hpp"
#include "lptn/motor_constant_fields.hpp"
#include "lptn/motor_constants.hpp"

namespace lptn::check {
namespace {

// Why a cycle with one of the calibration's names is not its data.
constexpr const char* kOtherFile = "same name, another file";
constexpr const char* kOtherMap = "same file, read through another data map";

// "3" or "0.14": a constant as a person reads it.
std::string shown(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Constants are read from text: equal files give equal doubles, so any difference is a real one
// (a relative 1e-9 only forgives the last digit of a rewritten file).
bool differ(double a, double b) { return std::abs(a - b) > 1e-9 * std::max(std::abs(a), std::abs(b)); }

template <class T>
void compare_member(std::string_view name, const T& data, const T& calibration, std::vector<std::string>& out) {
  if constexpr (std::is_array_v<T>) {
    for (std::size_t i = 0; i < std::extent_v<T>; ++i)
      if (differ(static_cast<double>(data[i]), static_cast<double>(calibration[i]))) {
        out.push_back(std::string(name) + "[" + std::to_string(i) + "] " + shown(static_cast<double>(data[i])) +
                      " (calibration: " + shown(static_cast<double>(calibration[i])) + ")");
        return;  // one line per key
      }
  } else if constexpr (std::is_arithmetic_v<T>) {
    if (differ(static_cast<double>(data), static_cast<double>(calibration)))
      out.push_back(std::string(name) + " " + shown(static_cast<double>(data)) + " (calibration: " +
                    shown(static_cast<double>(calibration)) + ")");
  }
}

// A data map as the words name it: its file, or that there was none.
std::string map_name(const std::string& file, const std::string& sha256) {
  if (sha256.empty()) return "none (lptn's own CSV)";
  return file.empty() ? "data map (given in code)" : file;
}

}  // namespace

bool Provenance::all_seen() const { return unseen() == 0 && constants.empty(); }

std::size_t Provenance::unseen() const {
  return static_cast<std::size_t>(std::count_if(cycles.begin(), cycles.end(), [](const auto& c) { return !c.seen; }));
}

std::vector<std::string> Provenance::unseen_names() const {
  std::vector<std::string> out;
  for (const CycleProvenance& c : cycles)
    if (!c.seen) out.push_back(c.name);
  return out;
}

bool Provenance::other_map() const {
  return std::any_of(cycles.begin(), cycles.end(), [](const auto& c) { return !c.seen && c.why == kOtherMap; });
}

std::string Provenance::summary() const {
  std::string out;
  const std::size_t n = unseen();
  if (n > 0) {
    std::size_t renamed = 0, remapped = 0;
    const CycleProvenance* first_remapped = nullptr;
    for (const CycleProvenance& c : cycles) {
      if (c.seen) continue;
      renamed += c.why == kOtherFile;
      if (c.why == kOtherMap && remapped++ == 0) first_remapped = &c;
    }
    const std::size_t unknown = n - renamed - remapped;
    std::vector<std::string> parts;
    if (remapped > 0)
      parts.push_back((remapped == n ? std::string("the calibration's files") : std::to_string(remapped) + " of them its files") +
                      " read through another data map: " + first_remapped->maps);
    if (renamed > 0)
      parts.push_back(renamed == n ? "the calibration's cycle names, other files"
                                   : std::to_string(renamed) + " with the calibration's cycle names but other files");
    if (unknown == n) parts.push_back("names it does not know");
    else if (unknown > 0 && remapped > 0) parts.push_back(std::to_string(unknown) + " with names it does not know");
    out = std::to_string(n) + " of " + std::to_string(cycles.size()) + " cycles (";
    for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? "; " : "") + parts[i];
    out += ")";
  }
  if (!constants.empty()) {
    out += out.empty() ? "the data's motor.toml has other motor constants than the calibration's: "
                       : "; the data's motor.toml has other motor constants: ";
    for (std::size_t i = 0; i < constants.size() && i < 3; ++i) out += (i ? ", " : "") + constants[i];
    if (constants.size() > 3) out += ", ...";
  }
  return out;
}

Provenance provenance(const calibrate::CalibrationResult& calibration, const data::Dataset& dataset,
                      const std::optional<MotorFile>& data_motor) {
  std::map<std::string, const calibrate::DataFile*> record_of;  // the calibration's cycle -> its file's record
  for (const calibrate::DataFile& f : calibration.data) record_of[f.cycle] = &f;
  // A file is hashed once however many segments it holds, the files over the cores (a 200 h
  // dump is 600 MB of CSV: about a second of one core's hashing here).
  std::map<std::string, std::string> file_hash;
  std::vector<std::filesystem::path> to_hash;
  for (const data::Cycle& c : dataset.cycles)
    if (record_of.count(c.name) && file_hash.emplace(c.file.string(), std::string()).second) to_hash.push_back(c.file);
  const std::vector<std::string> hashes = hostio::sha256_files(to_hash, hostio::worker_threads());
  for (std::size_t i = 0; i < to_hash.size(); ++i) file_hash[to_hash[i].string()] = hashes[i];
  Provenance p;
  for (const data::Cycle& c : dataset.cycles) {
    CycleProvenance cp;
    cp.name = c.name;
    const auto known = record_of.find(c.name);
    if (known == record_of.end()) {
      cp.why = "not among the calibration's cycles";
    } else {
      const calibrate::DataFile& seen = *known->second;
      cp.seen = file_hash.at(c.file.string()) == seen.sha256;
      if (!cp.seen) {
        cp.why = kOtherFile;
      } else if (seen.map_recorded && seen.map_sha256 != c.map_sha256) {
        // The same bytes read as other columns, units or drives are not the data it was fitted to.
        cp.seen = false;
        cp.why = kOtherMap;
        cp.maps = "the calibration's " + map_name(seen.map_file, seen.map_sha256) + ", this reading's " +
                  map_name(c.map_file.string(), c.map_sha256);
      }
    }
    if (cp.seen) {
      const auto in = [&](const std::vector<std::string>& v) { return std::find(v.begin(), v.end(), c.name) != v.end(); };
      cp.role = in(calibration.train_cycles) ? "train" : in(calibration.test_cycles) ? "test" : "";
    }
    p.cycles.push_back(std::move(cp));
  }
  if (data_motor) {
    for_each_motor_constant([&](const MotorField& f, const auto& data, const auto& cal) { compare_member(f.name, data, cal, p.constants); },
                            data_motor->constants, calibration.motor.constants);
  }
  return p;
}

std::optional<MotorFile> motor_beside(const std::vector<std::string>& data_paths) {
  for (const std::string& d : data_paths) {
    const std::filesystem::path file = std::filesystem::path(d) / "motor.toml";
    std::error_code ec;
    if (!std::filesystem::is_directory(d, ec) || !std::filesystem::is_regular_file(file, ec)) continue;
    try {
      return load_motor_file(file);
    } catch (const MotorFileError&) {
      return std::nullopt;  // not the user's input here: a motor file they did not give is not judged
    }
  }
  return std::nullopt;
}

}  // namespace lptn::check
