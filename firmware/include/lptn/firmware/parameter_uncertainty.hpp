// How uncertain each calibrated parameter is, in the terms the observer uses: the standard
// deviation of ln(parameter). One function, called by the firmware on the exported header's
// kParamStdError, kParamCalibrated and kParamIdentifiable (exported_calibration.hpp) and by `lptn
// replay` on calibration.json's (tools/replay/calibrated_estimator.cpp): both carry the same figures.
//
//   calibrated, identifiable, with a standard error   std_error / value (first order in ln)
//   not identifiable (the data could not pin it: its  kNotIdentifiableLnStd, a wide prior: the
//   value is the motor file's guess)                   motor file's guess known within a factor
//   calibrated but no standard error (TD3, search      of 1.5 at 1 sigma. Why 1.5: a motor file's
//   methods, a version-1 file: unknown, not exact)     conductances come from a design estimate;
//                                                      the synthetic plant's truth sits from
//                                                      motor.toml's guesses at ln ratios of 0.29..0.64
//                                                      (RMS 0.43; ln 1.5 = 0.41), and textbook
//                                                      estimates of a convective conductance carry
//                                                      +-30..50 %.
//   pinned in the motor file (calibrate = false)      0: the user's stated value, taken as known
//                                                      (their error is absorbed by the fitted
//                                                      parameters, whose standard errors then hold
//                                                      it); fit a parameter to give it a spread
//   not positive (a share at 0)                       0: no ln; nothing to scale
// Plain constexpr C++, no heap: the firmware may include it.
#pragma once

namespace lptn::fw {

// ln 1.5: a not-identifiable (or never assessed) parameter's 1-sigma spread in ln terms.
inline constexpr double kNotIdentifiableLnStd = 0.4054651081081644;

// std_error: 1 sigma, physical units; NaN (or negative) where unknown.
constexpr double parameter_ln_std(double value, double std_error, bool calibrated, bool identifiable) {
  if (!(value > 0.0)) return 0.0;
  if (!identifiable) return kNotIdentifiableLnStd;
  if (!calibrated) return 0.0;
  const bool known = std_error == std_error && std_error >= 0.0;  // NaN compares unequal to itself
  return known ? std_error / value : kNotIdentifiableLnStd;
}

}  // namespace lptn::fw
