#!/usr/bin/env python3
"""Bad bus maps, both routes: the build's glue generator (lptn-bus-codegen) and `lptn convert --bus`
must refuse each with one line naming the map, the line and the key, and say the same thing;
nothing is written. Both read the map with can/bus, so they agree by construction; the words, the
lines and that nothing is written are what this holds.

    check_bad_maps.py BUS_CODEGEN LPTN FOREIGN_DIR

Each case is the foreign map (FOREIGN_DIR/bus.toml) with one edit, written into a scratch
directory beside a copy of its DBC.
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

# (name, edit(text) -> text, line the refusal must name, words it must contain)
CASES = [
    ("unknown input", lambda t: t.replace("[inputs.rotor_c]", "[inputs.rotor_temp]"), 41,
     "[inputs.rotor_temp]: unknown input 'rotor_temp'"),
    ("message the DBC lacks", lambda t: t.replace('message = "TCU_Drive"', 'message = "TCU_Drv"', 1), 20,
     "[inputs.torque_nm] message: TCU_Drv is not a message of converter.dbc"),
    ("signal the DBC lacks", lambda t: t.replace('signal = "PhaseCurrRms"', 'signal = "PhaseCurrent"'), 13,
     "[inputs.current_a] signal: TCU_MotorState has no signal PhaseCurrent"),
    ("unit of another quantity", lambda t: t.replace('signal = "MotAngSpd"', 'signal = "PhaseCurrRms"'), 8,
     "[inputs.speed_rpm] signal: TCU_MotorState.PhaseCurrRms cannot be speed_rpm: its unit 'A' is not one of rpm"),
    ("rad/s without its scale", lambda t: re.sub(r"scale = 9\.5[^\n]*\n", "", t), 8,
     "its unit is 'rad/s': to give rpm it needs scale = 9.5493 and offset = 0, not scale = 1 and offset = 0"),
    ("kelvin without its offset", lambda t: re.sub(r"offset = -273\.15[^\n]*\n", "", t), 29,
     "its unit is 'K': to give degC it needs scale = 1 and offset = -273.15, not scale = 1 and offset = 0"),
    ("unknown key", lambda t: t.replace('signal = "TrqAct"\n', 'signal = "TrqAct"\nfactor = 2\n'), 22,
     "[inputs.torque_nm]: unknown key 'factor'"),
    ("a message that carries no input", lambda t: t + '\n[messages.VCU_Command]\nalive_counter = "TrqReq"\n', 67,
     "[messages.VCU_Command]: VCU_Command carries no input of this map"),
    ("a counter that is no counter", lambda t: t.replace('alive_counter = "Cntr"', 'alive_counter = "TrqAct"'), 51,
     "[messages.TCU_Drive] alive_counter: TrqAct is no counter"),
    ("a CRC that is no CRC-8", lambda t: t.replace('crc = "Crc8"', 'crc = "InvState"'), 47,
     "[messages.TCU_MotorState] crc: InvState is no CRC-8"),
    ("a CRC without its data id", lambda t: t.replace("data_id = 0x1027\n", ""), 47,
     "[messages.TCU_MotorState] crc: data_id (0..65535) is missing"),
    ("a MaxDeltaCounter the counter cannot reach", lambda t: t.replace("max_delta_counter = 3", "max_delta_counter = 256"), 52,
     "[messages.TCU_Drive] max_delta_counter: a whole number from 1 to 255"),
    ("the multiplexor as an input", lambda t: t.replace('signal = "RotorTemp"', 'signal = "PageId"'), 43,
     "[inputs.rotor_c] signal: PageId is TCU_Thermal's multiplexor"),
    ("a required input left out", lambda t: re.sub(r"\[inputs\.current_a\]\n[^\[]*", "", t), 1,
     "[inputs.current_a] is missing: the estimator cannot run without it"),
    ("a scale of zero", lambda t: t.replace("scale = 0.000277777777777778", "scale = 0"), 35,
     "[inputs.airflow_m3s] scale: 0 would make the input a constant"),
    ("a DBC that is not there", lambda t: t.replace('dbc = "converter.dbc"', 'dbc = "missing.dbc"'), 4, "dbc: "),
    ("an output on an input's id", lambda t: t.replace("LPTN_Margin = 0x18FF4227", "LPTN_Margin = 0x18FF1027"), 62,
     "[outputs] LPTN_Margin: id 0x18FF1027 is TCU_MotorState's too; give LPTN_Margin another id in [outputs]"),
    ("two outputs on one id", lambda t: t.replace("LPTN_Innovation = 0x344", "LPTN_Innovation = 0x18FF4127"), 64,
     "[outputs] LPTN_Innovation: id 0x18FF4127 is LPTN_TemperatureStd's too"),
    ("an output the estimator does not send", lambda t: t.replace("LPTN_Innovation = 0x344", "LPTN_Debug = 0x344"), 64,
     "[outputs]: unknown key 'LPTN_Debug' (LPTN_Temperatures, LPTN_TemperatureStd, LPTN_Margin, LPTN_Status, LPTN_Innovation, LPTN_Cooling)"),
    ("an output id no frame can have", lambda t: t.replace("LPTN_Innovation = 0x344", "LPTN_Innovation = 0x20000000"), 64,
     "[outputs] LPTN_Innovation: a CAN id, 0..0x1FFFFFFF (above 0x7FF an extended one)"),
    ("not TOML", lambda t: t.replace('[inputs.voltage_v]', '[inputs.voltage_v'), 23, "not TOML"),
]


def refusal(command, cwd):
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True)
    lines = [line for line in done.stderr.splitlines() if line]
    return done.returncode, lines


def main():
    codegen, lptn, foreign = (os.path.abspath(arg) for arg in sys.argv[1:4])
    original = open(os.path.join(foreign, "bus.toml"), encoding="utf-8").read()
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        shutil.copy(os.path.join(foreign, "converter.dbc"), scratch)
        for name, edit, line, words in CASES:
            text = edit(original)
            if text == original:
                failures.append(f"{name}: the edit changed nothing (the foreign map changed?)")
                continue
            bad = os.path.join(scratch, "bad.toml")
            open(bad, "w", encoding="utf-8").write(text)
            out = os.path.join(scratch, "glue.hpp")
            build_code, build = refusal([codegen, "--bus", bad, "--codecs", "c.hpp", "--codec-namespace",
                                         "n::dbc", "--out", out], scratch)
            log = os.path.join(scratch, "out.log")
            run_code, runtime = refusal([lptn, "convert", "--bus", bad, "--in", bad, "--out", log], scratch)
            prefix = f"{bad}:{line}: "
            for route, code, said, lead in (("build", build_code, build, ""), ("run time", run_code, runtime, "lptn: error: ")):
                if code == 0 or len(said) != 1:
                    failures.append(f"{name} ({route}): exit {code}, said {said!r}; expected one line")
                    continue
                if not said[0].startswith(lead + prefix) or words not in said[0]:
                    failures.append(f"{name} ({route}): said {said[0]!r}; expected {lead + prefix}...{words}...")
            if build and runtime and name not in ("a DBC that is not there", "not TOML"):
                if build[0] != runtime[0][len("lptn: error: "):]:
                    failures.append(f"{name}: the routes disagree:\n  build:    {build[0]}\n  run time: {runtime[0]}")
            for written in (out, log):
                if os.path.exists(written):
                    failures.append(f"{name}: {os.path.basename(written)} was written")
                    os.unlink(written)
    for failure in failures:
        print(failure)
    print(f"{len(CASES)} bad maps, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
