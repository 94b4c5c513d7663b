#pragma once
// Shared helpers: a scratch directory per test and a CSV writer driven by analytic signals.

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace lptn::data::test {

namespace fs = std::filesystem;

// Tests run as separate processes under ctest, possibly in parallel: pid + random keeps them apart.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("lptn_data_test_" + std::to_string(::getpid()) + "_" + std::to_string(rd()) + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const fs::path& path() const { return path_; }

  fs::path write(const std::string& name, std::string_view content) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    return p;
  }

 private:
  fs::path path_;
};

struct Col {
  std::string name;
  // nullopt -> empty cell
  std::function<std::optional<double>(std::size_t row, double t)> value;
};

inline std::string fmt_value(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline std::string build_csv(const std::vector<double>& times, const std::vector<Col>& cols,
                             std::string_view eol = "\n") {
  std::string out;
  for (std::size_t c = 0; c < cols.size(); ++c) out += (c ? "," : "") + cols[c].name;
  out += eol;
  for (std::size_t i = 0; i < times.size(); ++i) {
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (c) out += ',';
      if (const auto v = cols[c].value(i, times[i])) out += fmt_value(*v);
    }
    out += eol;
  }
  return out;
}

inline std::vector<double> regular_times(std::size_t n, double dt) {
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(i) * dt;
  return t;
}

// The standard analytic signals (pole_pairs 2).
inline double speed_of(double t) { return 1000.0 + 2.0 * t; }
inline double torque_of(double t) { return 500.0 - t; }
inline double current_of(double t) { return 100.0 + 0.5 * t; }
inline double frequency_of(double t) { return speed_of(t) * 2.0 / 60.0; }
inline double voltage_of(double) { return 1000.0; }
inline double airflow_of(double t) { return 1.5 + 0.001 * t; }
inline double ambient_of(double t) { return 20.0 + 0.01 * t; }
inline double stator_of(double t) { return 40.0 + 0.1 * t; }
inline double rotor_of(double t) { return 50.0 + 0.1 * t; }

inline Col time_col() {
  return {"time_s", [](std::size_t, double t) { return std::optional<double>(t); }};
}

inline Col signal_col(std::string name, double (*f)(double)) {
  return {std::move(name), [f](std::size_t, double t) { return std::optional<double>(f(t)); }};
}

// time, all required channels and torque/voltage, every channel on every row.
inline std::vector<Col> standard_cols() {
  return {time_col(),
          signal_col("speed_rpm", speed_of),
          signal_col("torque_nm", torque_of),
          signal_col("current_a", current_of),
          signal_col("frequency_hz", frequency_of),
          signal_col("voltage_v", voltage_of),
          signal_col("airflow_m3s", airflow_of),
          signal_col("ambient_c", ambient_of),
          signal_col("stator_winding_c", stator_of)};
}

// Replace the column `name` in `cols`.
inline void replace_col(std::vector<Col>& cols, const Col& col) {
  for (Col& c : cols) {
    if (c.name == col.name) c = col;
  }
}

}  // namespace lptn::data::test
