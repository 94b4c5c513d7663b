"""The combined RMSE of a calibration's metrics: stator and rotor residuals pooled, each sensor
weighted by its samples (a dump without rotor readings: the stator's alone). What the demo and the
calibration benchmarks compare TD3 with LM by; one definition for all of them (imported with
scripts/ on PYTHONPATH or beside the importing script).
"""
import json
import math


def combined(m):
    """Pooled RMSE of one side's metrics (calibration.json's metrics.train or metrics.test)."""
    ns, nr = m["samples_stator"], m.get("samples_rotor", 0)
    return math.sqrt((m["rmse_stator_k"] ** 2 * ns + m.get("rmse_rotor_k", 0.0) ** 2 * nr) / (ns + nr))


def pooled(path, side="test"):
    """Pooled RMSE of a calibration.json's train or test cycles."""
    with open(path) as f:
        return combined(json.load(f)["metrics"][side])

