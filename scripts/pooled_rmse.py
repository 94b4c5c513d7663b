#!/usr/bin/env python3
"""The combined RMSE of a calibration's metrics: stator and rotor residuals pooled, each sensor
weighted by its samples (a dump without rotor readings: the stator's alone). What the demo and the
calibration benchmarks compare TD3 with LM by; one definition for all of them.

  scripts/pooled_rmse.py CALIBRATION.json [SIDE]   prints the pooled RMSE of SIDE (default test) in K
"""
import json
import math
import sys


def combined(m):
    """Pooled RMSE of one side's metrics (calibration.json's metrics.train or metrics.test)."""
    ns, nr = m["samples_stator"], m.get("samples_rotor", 0)
    return math.sqrt((m["rmse_stator_k"] ** 2 * ns + m.get("rmse_rotor_k", 0.0) ** 2 * nr) / (ns + nr))


def pooled(path, side="test"):
    """Pooled RMSE of a calibration.json's train or test cycles."""
    with open(path) as f:
        return combined(json.load(f)["metrics"][side])


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__.strip().splitlines()[-1].strip())
    print(f"{pooled(*sys.argv[1:]):.6f}")
