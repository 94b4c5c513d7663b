// What a bus map (bus.toml) may say: the estimator's inputs by their fleet-dump column, the units a
// converter's DBC may give them in, and the estimator's own frames that [outputs] may move. The one
// list for both routes: the run-time reader (bus_map.cpp) checks maps against it, and the build's
// glue generator (can/codegen's lptn-bus-codegen) reads maps with that same reader.
#pragma once

#include "lptn/firmware/input.hpp"

namespace lptn::bus {

// The order is the columns' order in trainer/data/channels.hpp; required inputs are firmware's
// kRequiredInputs. `enumerator` is the input's fw::Input name, for the generated glue.
struct InputWord {
  const char* column;
  fw::Input input;
  bool required;
  const char* unit;  // canonical
  const char* enumerator;
};
inline constexpr InputWord kInputWords[] = {
    {"speed_rpm", fw::Input::speed, true, "rpm", "speed"},
    {"torque_nm", fw::Input::torque, false, "Nm", "torque"},
    {"current_a", fw::Input::current, true, "A", "current"},
    {"frequency_hz", fw::Input::frequency, true, "Hz", "frequency"},
    {"voltage_v", fw::Input::voltage, false, "V", "voltage"},
    {"airflow_m3s", fw::Input::airflow, true, "m3/s", "airflow"},
    {"ambient_c", fw::Input::ambient, true, "degC", "ambient"},
    {"stator_winding_c", fw::Input::stator_sensor, false, "degC", "stator_sensor"},
    {"rotor_c", fw::Input::rotor_sensor, false, "degC", "rotor_sensor"},
};

// A DBC unit's spelling -> canonical unit: canonical = value * factor + offset. A map must scale a
// signal in another unit of the same quantity by exactly this; a signal whose unit is of another
// quantity cannot carry the input at all. Units not listed (or none) are taken as the map says,
// with a warning. The factors are the nearest doubles to 60/2pi, 1/60, 5/9, -160/9, ...
struct UnitWord {
  const char* spelling;
  const char* canonical;
  double factor, offset;
};
inline constexpr UnitWord kUnitWords[] = {
    {"rpm", "rpm", 1.0, 0.0},
    {"1/min", "rpm", 1.0, 0.0},
    {"min-1", "rpm", 1.0, 0.0},
    {"U/min", "rpm", 1.0, 0.0},
    {"r/min", "rpm", 1.0, 0.0},
    {"rev/min", "rpm", 1.0, 0.0},
    {"rad/s", "rpm", 9.549296585513721, 0.0},
    {"rps", "rpm", 60.0, 0.0},
    {"Hz", "Hz", 1.0, 0.0},
    {"kHz", "Hz", 1000.0, 0.0},
    {"A", "A", 1.0, 0.0},
    {"kA", "A", 1000.0, 0.0},
    {"mA", "A", 0.001, 0.0},
    {"V", "V", 1.0, 0.0},
    {"kV", "V", 1000.0, 0.0},
    {"mV", "V", 0.001, 0.0},
    {"Nm", "Nm", 1.0, 0.0},
    {"N.m", "Nm", 1.0, 0.0},
    {"N*m", "Nm", 1.0, 0.0},
    {"N m", "Nm", 1.0, 0.0},
    {"kNm", "Nm", 1000.0, 0.0},
    {"m3/s", "m3/s", 1.0, 0.0},
    {"m^3/s", "m3/s", 1.0, 0.0},
    {"m\302\263/s", "m3/s", 1.0, 0.0},  // m³/s in UTF-8, as can/dbc reads a DBC
    {"m3/min", "m3/s", 0.016666666666666666, 0.0},
    {"m3/h", "m3/s", 0.0002777777777777778, 0.0},
    {"l/s", "m3/s", 0.001, 0.0},
    {"degC", "degC", 1.0, 0.0},
    {"\302\260C", "degC", 1.0, 0.0},  // °C
    {"deg C", "degC", 1.0, 0.0},
    {"C", "degC", 1.0, 0.0},
    {"Cel", "degC", 1.0, 0.0},
    {"K", "degC", 1.0, -273.15},
    {"degF", "degC", 0.5555555555555556, -17.77777777777778},
    {"\302\260F", "degC", 0.5555555555555556, -17.77777777777778},  // °F
};

// How close a map's scale and offset must come to a unit's conversion (relative; offsets also
// absolute, in the input's unit): a DBC's factor is exact, a hand-written 9.5493 is not.
inline constexpr double kUnitTolerance = 0.001;
// AUTOSAR E2E's MaxDeltaCounter where a map gives none: one lost frame is tolerated, two are not.
inline constexpr int kDefaultMaxDeltaCounter = 2;

// The estimator's output frames (can/codecs/lptn.dbc's LPTN_* messages) in the order
// fw::pack_outputs fills them; a map may move them to other CAN ids ([outputs]).
// firmware's output_frames.hpp static_asserts this order against the codecs' names.
inline constexpr const char* kOutputFrameNames[] = {"LPTN_Temperatures", "LPTN_TemperatureStd", "LPTN_Margin",
                                                    "LPTN_Status",       "LPTN_Innovation",     "LPTN_Cooling"};

}  // namespace lptn::bus
