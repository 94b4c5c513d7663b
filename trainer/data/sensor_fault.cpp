#include "trainer/data/sensor_fault.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "hostio/bad_input.hpp"
#include "trainer/data/dataset.hpp"

namespace lptn::data {
namespace {

// A transmitter's span error beyond this is not a gain fault but a wrong sensor type.
constexpr double kMaxGain = 0.5;

std::vector<std::string_view> fields(std::string_view text) {
  std::vector<std::string_view> out;
  std::size_t from = 0;
  for (;;) {
    const std::size_t colon = text.find(':', from);
    out.push_back(text.substr(from, colon == std::string_view::npos ? std::string_view::npos : colon - from));
    if (colon == std::string_view::npos) return out;
    from = colon + 1;
  }
}

}  // namespace

const char* to_string(FaultShape s) {
  switch (s) {
    case FaultShape::offset: return "offset";
    case FaultShape::gain: return "gain";
    case FaultShape::drift: return "drift";
  }
  return "?";
}

const char* sensor_name(Channel sensor) { return sensor == Channel::rotor_c ? "rotor" : "stator"; }

double SensorFault::weight(std::size_t i, std::size_t n) const {
  if (i < first || first >= n) return 0;
  if (shape != FaultShape::drift) return 1;
  return static_cast<double>(i - first + 1) / static_cast<double>(n - first);
}

double SensorFault::reading(double t_c, std::size_t i, std::size_t n) const {
  const double w = weight(i, n);
  return shape == FaultShape::gain ? t_c * (1 + w * size) : t_c + w * size;
}

double SensorFault::corrected(double reading_c, std::size_t i, std::size_t n) const {
  const double w = weight(i, n);
  return shape == FaultShape::gain ? reading_c / (1 + w * size) : reading_c - w * size;
}

SensorFaultSpec parse_sensor_fault(std::string_view text) {
  // Appended, not `"'" + std::string(text) + "'"`: GCC 12's -Wrestrict misfires on that at -O3.
  std::string quoted(1, '\'');
  quoted.append(text).push_back('\'');
  const std::vector<std::string_view> f = fields(text);
  if (f.size() != 4)
    throw hostio::BadInput(quoted + ": expected SENSOR:SHAPE:SIZE:FIRST, e.g. stator:offset:3.0:cycle_05_freight");
  SensorFaultSpec spec;
  if (f[0] == "stator") spec.fault.sensor = Channel::stator_winding_c;
  else if (f[0] == "rotor") spec.fault.sensor = Channel::rotor_c;
  else throw hostio::BadInput(quoted + ": sensor '" + std::string(f[0]) + "' is not stator or rotor");
  if (f[1] == "offset") spec.fault.shape = FaultShape::offset;
  else if (f[1] == "gain") spec.fault.shape = FaultShape::gain;
  else if (f[1] == "drift") spec.fault.shape = FaultShape::drift;
  else throw hostio::BadInput(quoted + ": shape '" + std::string(f[1]) + "' is not offset, gain or drift");
  const char* end = f[2].data() + f[2].size();
  const auto [ptr, ec] = std::from_chars(f[2].data() + (!f[2].empty() && f[2][0] == '+'), end, spec.fault.size);
  if (ec != std::errc() || ptr != end || !std::isfinite(spec.fault.size))
    throw hostio::BadInput(quoted + ": size '" + std::string(f[2]) + "' is not a number");
  if (spec.fault.shape == FaultShape::gain && !(std::abs(spec.fault.size) < kMaxGain))
    throw hostio::BadInput(quoted + ": a gain's size is relative (0.03 reads 3 % high), within +-0.5");
  if (f[3].empty()) throw hostio::BadInput(quoted + ": FIRST (the first faulty cycle) is empty");
  spec.first_cycle = std::string(f[3]);
  return spec;
}

std::string format_sensor_fault(const SensorFault& fault, const std::string& first_cycle) {
  char size[32];
  std::snprintf(size, sizeof size, fault.shape == FaultShape::gain ? "%+.4f" : "%+.2f", fault.size);
  return std::string(sensor_name(fault.sensor)) + ":" + to_string(fault.shape) + ":" + size + ":" + first_cycle;
}

CycleOrder cycle_order(const Dataset& dataset) {
  CycleOrder order;
  order.file_index.reserve(dataset.cycles.size());
  for (std::size_t i = 0; i < dataset.cycles.size(); ++i) {
    if (i > 0 && dataset.cycles[i].file != dataset.cycles[i - 1].file) ++order.files;
    order.file_index.push_back(order.files);
  }
  if (!dataset.cycles.empty()) ++order.files;
  return order;
}

SensorFault resolve(const SensorFaultSpec& spec, const Dataset& dataset) {
  const CycleOrder order = cycle_order(dataset);
  for (std::size_t i = 0; i < dataset.cycles.size(); ++i)
    if (dataset.cycles[i].name == spec.first_cycle || dataset.cycles[i].file.stem().string() == spec.first_cycle) {
      SensorFault f = spec.fault;
      f.first = order.file_index[i];
      return f;
    }
  std::string known;
  for (const Cycle& c : dataset.cycles) known += (known.empty() ? "" : ", ") + c.name;
  throw hostio::BadInput("no cycle named '" + spec.first_cycle + "' in the data (cycles: " + known + ")");
}

void correct_readings(Dataset& dataset, const SensorFault& fault) {
  const CycleOrder order = cycle_order(dataset);
  for (std::size_t i = 0; i < dataset.cycles.size(); ++i) {
    std::vector<float>& y = dataset.cycles[i].samples[index_of(fault.sensor)];
    for (float& v : y)
      if (!std::isnan(v)) v = static_cast<float>(fault.corrected(v, order.file_index[i], order.files));
  }
}

void correct_readings(Dataset& dataset, const std::vector<std::string>& specs) {
  for (const std::string& spec : specs) correct_readings(dataset, resolve(parse_sensor_fault(spec), dataset));
}

}  // namespace lptn::data
