// One model step's inputs: what the converter reports on CAN (or a fleet dump recorded).
#pragma once

namespace lptn {

template <class R>
struct Inputs {
  R speed_rpm = R(0);
  R torque_nm = R(0);  // used only when has_torque
  R current_a = R(0);  // stator phase current, RMS
  R frequency_hz = R(0);
  R voltage_v = R(0);  // line, RMS fundamental; used only when has_voltage
  R airflow_m3s = R(0);
  R ambient_c = R(20);
  // Torque and voltage refine the loss model where the bus carries them; without them the model
  // falls back to nameplate-based estimates (see paper_model.hpp).
  bool has_torque = false;
  bool has_voltage = false;
};

}  // namespace lptn
