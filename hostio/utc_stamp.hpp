// The present time as lptn's outputs stamp it (calibration.json's created_utc, the report's
// generated_utc): "2026-11-21T10:00:00Z".
#pragma once

#include <ctime>
#include <string>

namespace lptn::hostio {

inline std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);  // thread-safe, unlike std::gmtime
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace lptn::hostio
