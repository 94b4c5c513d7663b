// The longest gap in each input that is bridged before the input counts as missing. The trainer's
// loader interpolates across gaps up to this long (trainer/data/channels.hpp; longer ones cut or
// mask the cycle), and the firmware holds an input's last good value this long past its timeout
// (lptn/firmware/estimator_config.hpp), so that the model runs on board on inputs no staler than
// those it was calibrated on.
#pragma once

namespace lptn::grace {

// Speed, torque, current, frequency and voltage follow the driver's commands within seconds, and
// the losses follow them at once.
inline constexpr double kElectricalS = 2.0;
// Airflow and the temperatures act through the motor's thermal time constants (minutes): a value
// some seconds old changes the estimate little.
inline constexpr double kAirflowS = 10.0;
// Stator winding and rotor sensors, in the trainer's loader only: the firmware fuses each reading
// once, as it arrives, and holds none.
inline constexpr double kTemperatureSensorS = 10.0;
// The cooling air's inlet temperature changes with the weather and the route, slowest of all.
inline constexpr double kAmbientS = 120.0;

}  // namespace lptn::grace
