// A temperature sensor that reads wrong while the motor is fine: an offset from some cycle on, a
// gain, a slow drift. One definition for everyone who needs it: `lptn generate` puts such a fault
// into a dump's readings, `lptn diagnose` names one it finds in those terms, and `lptn calibrate
// --sensor-fault` takes it back out of the readings, so that the physical parameters are fitted
// to what the sensor would have read.
//
//   offset  from cycle `first` on, the sensor reads `size` K high (a replaced or re-wired sensor,
//           a new transmitter's zero)
//   gain    from cycle `first` on, it reads (1 + size) times the temperature in °C (a transmitter's
//           span: 0 °C reads right, 100 °C reads 100 (1 + size))
//   drift   an offset growing linearly in the dump's cycle order, from `size` / (n - first) K in
//           cycle `first` to `size` K in the last (an ageing sensor; a sensor drifts over weeks of
//           calendar time, so within one cycle of an hour or two its offset is constant)
// Cycles count in the dump's order (files sorted by name); the segments of one file after a split
// share its index.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "trainer/data/channels.hpp"

namespace lptn::data {

struct Dataset;

enum class FaultShape { offset, gain, drift };
const char* to_string(FaultShape s);

struct SensorFault {
  Channel sensor = Channel::stator_winding_c;  // stator_winding_c or rotor_c
  FaultShape shape = FaultShape::offset;
  double size = 0;        // offset, drift: K; gain: relative
  std::size_t first = 0;  // the first faulty cycle (0-based, in the dump's order)

  // The fault's share in cycle `i` of `n`: 0 before `first`, 1 after for an offset or a gain, the
  // drift's linear growth up to 1 in the last cycle.
  double weight(std::size_t i, std::size_t n) const;
  // What the sensor reads in cycle `i` of `n` where the temperature is `t_c`.
  double reading(double t_c, std::size_t i, std::size_t n) const;
  // The temperature a reading stands for: reading()'s inverse.
  double corrected(double reading_c, std::size_t i, std::size_t n) const;
};

// "stator" or "rotor" for the sensor's channel.
const char* sensor_name(Channel sensor);

// The command-line form, SENSOR:SHAPE:SIZE:FIRST ("stator:offset:3.0:cycle_05_freight"): FIRST is
// a cycle's name (lptn calibrate) or a 1-based cycle number (lptn generate), resolved by the caller.
struct SensorFaultSpec {
  SensorFault fault;        // `first` unresolved
  std::string first_cycle;  // as written
};
// Throws BadInput with a message naming what is wrong in `text`.
SensorFaultSpec parse_sensor_fault(std::string_view text);
std::string format_sensor_fault(const SensorFault& fault, const std::string& first_cycle);

// The dump's cycle order as the faults count it: the index of each cycle's file among the dump's
// files, and their number.
struct CycleOrder {
  std::vector<std::size_t> file_index;  // per cycle of the dataset
  std::size_t files = 0;
};
CycleOrder cycle_order(const Dataset& dataset);

// `spec.fault` with `first` resolved against the dataset's cycle names (a segment's name or its
// file's stem). Throws BadInput naming the cycle where none has that name.
SensorFault resolve(const SensorFaultSpec& spec, const Dataset& dataset);

// Every reading of the fault's sensor replaced by what it stands for (corrected()).
void correct_readings(Dataset& dataset, const SensorFault& fault);
// The same for each SENSOR:SHAPE:SIZE:FIRST in `specs` (FIRST a cycle's name), in order. Throws
// BadInput naming the spec that cannot be parsed or resolved.
void correct_readings(Dataset& dataset, const std::vector<std::string>& specs);

}  // namespace lptn::data
