#!/usr/bin/env python3
"""The calibration benchmark's table (scripts/bench-calibration.sh writes the runs it reads).

For each method over its seeds: the combined test RMSE (stator and rotor residuals pooled) as
median and worst, its ratio to Levenberg-Marquardt's, how many seeds reached 1.1x LM, wall time,
model steps simulated and gradient updates, train and test RMSE per sensor (medians), and the
parameter error against the plant's truth (median over seeds of the largest |ln(value/truth)|).

  scripts/bench-calibration-summary.py OUT_DIR
"""
import glob
import json
import math
import os
import statistics
import sys

from pooled_rmse import combined


def main(out):
    truth = json.load(open(os.path.join(out, "fleet", "truth.json")))["parameters"]
    runs = {}
    for path in sorted(glob.glob(os.path.join(out, "*-*.json"))):
        method, seed = os.path.basename(path)[:-5].rsplit("-", 1)
        if not seed.isdigit():
            continue
        j = json.load(open(path))
        wall = path[:-5] + ".wall"
        details = j["method"].get("details", {})
        settings = j["method"].get("settings", {})
        if "updates" not in details and "updates_per_episode" in settings:  # the paper's formulations: updates after
            details["updates"] = settings["updates_per_episode"] * max(0, details.get("episodes", 0) - settings.get("random_episodes", 0))
        error = max(abs(math.log(p["value"] / truth[p["name"]]["value"]))
                    for p in j["parameters"] if p.get("calibrated") and p["name"] in truth)
        runs.setdefault(method, []).append({
            "seed": int(seed),
            "test": combined(j["metrics"]["test"]),
            "train": combined(j["metrics"]["train"]),
            "m": j["metrics"],
            "wall": float(open(wall).read()) if os.path.exists(wall) else float("nan"),
            "steps": details.get("simulated_steps"),  # not counted by the paper's formulations
            "updates": details.get("updates"),
            "param_error": error,
        })
    if "lm" not in runs:
        sys.exit(f"{out}: no lm-1.json to compare with")
    lm = runs["lm"][0]["test"]
    order = ["lm", "td3", "td3-paper", "td3-episode", "random-search", "cma-es"]
    print(f"LM's combined test RMSE: {lm:.4f} K; 1.1x = {1.1 * lm:.4f} K\n")
    print("| method | seeds | test RMSE median / worst | ratio to LM median / worst | reached 1.1x | wall time median / worst "
          "| model steps | updates | train RMSE stator / rotor | test RMSE stator / rotor | parameter error (max abs ln) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    med = statistics.median
    for method in sorted(runs, key=lambda m: order.index(m) if m in order else len(order)):
        r = runs[method]
        tests = [x["test"] for x in r]
        walls = [x["wall"] for x in r]
        steps = [x["steps"] for x in r if x["steps"] is not None]
        updates = [x["updates"] for x in r if x["updates"] is not None]
        reached = sum(t <= 1.1 * lm for t in tests)
        side = lambda s, k: med([x["m"][s][k] for x in r])
        print(f"| {method} | {len(r)} | {med(tests):.3f} / {max(tests):.3f} K | {med(tests) / lm:.3f} / {max(tests) / lm:.3f} "
              f"| {reached} of {len(r)} | {med(walls):.0f} / {max(walls):.0f} s "
              f"| {f'{med(steps) / 1e6:.0f} M' if steps else '-'} | {f'{med(updates):.0f}' if updates else '-'} "
              f"| {side('train', 'rmse_stator_k'):.3f} / {side('train', 'rmse_rotor_k'):.3f} K "
              f"| {side('test', 'rmse_stator_k'):.3f} / {side('test', 'rmse_rotor_k'):.3f} K "
              f"| {med([x['param_error'] for x in r]):.3f} |")
    print()
    for method in runs:
        if method == "lm":
            continue
        print(method + ": " + ", ".join(f"seed {x['seed']} {x['test']:.3f} K ({x['test'] / lm:.3f}x, {x['wall']:.0f} s)"
                                         for x in sorted(runs[method], key=lambda x: x["seed"])))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "bench-out")
