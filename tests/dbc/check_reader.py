#!/usr/bin/env python3
"""Holds the run-time DBC reader (can/dbc, through dump_dbc) to the build-time generator's
reading (can/codecs/dbc_codegen.py) on every DBC file the project has: our own, the generator's good,
warning and bad cases, the foreign converter's, and the real-world corpus (ctest dbc.reader).

    check_reader.py --generator can/codecs/dbc_codegen.py --dump DUMP_DBC FILE_OR_DIR...

For each file both must agree on the outcome: the same refusal (line and reason), or the same
frames (ids, lengths, every signal's layout, scaling, unit and multiplexing, cycle times), and
for 20 pseudo-random payloads per message the same raw and physical value of every signal the
payload carries, the multiplexor's value deciding which. The generator's frame_bits() is the
reference for the bits; the physical value is raw * factor + offset in doubles, as the generated
NAME_decode() computes it.
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys

FRAMES = 20
MASK = (1 << 64) - 1


def load_generator(path):
    spec = importlib.util.spec_from_file_location("dbc_codegen", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def xorshift(state):
    state ^= (state << 13) & MASK
    state ^= state >> 7
    state ^= (state << 17) & MASK
    return state


def raw_value(gen, signal, data):
    value = 0
    for index, bit in enumerate(gen.frame_bits(signal)):
        if data[bit // 8] >> (bit % 8) & 1:
            value |= 1 << index
    if signal.signed and value >> (signal.length - 1) & 1:
        value -= 1 << signal.length
    return value


def expected(gen, path):
    warnings = gen.Warnings()
    try:
        dbc = gen.Parser(gen.tokenize(gen.read_text(path)), warnings).parse()
        gen.Checker(dbc, warnings, gen.NO_NODE).run()
    except gen.DbcError as error:
        return {"error": f"{error.line}: {error.reason}"}
    messages = []
    for m in (m for m in dbc.messages if m.generated):
        signals = [{"name": s.name, "start": s.start, "length": s.length, "big_endian": s.big_endian,
                    "signed": s.signed, "factor": s.factor.double, "offset": s.offset.double, "unit": s.unit,
                    "multiplexor": s.multiplexor,
                    "mux_ranges": [list(r) for r in s.mux_ranges] if s.multiplexed else None}
                   for s in m.signals]
        frames, state = [], 0x9E3779B97F4A7C15 ^ m.can_id
        for _ in range(FRAMES):
            data = []
            for _ in range(m.dlc):
                state = xorshift(state)
                data.append(state >> 56)
            values = {}
            multiplexor = m.multiplexor
            mux_raw = raw_value(gen, multiplexor, data) if multiplexor else None
            for s in m.signals:
                if s.multiplexed and not any(low <= mux_raw <= high for low, high in s.mux_ranges):
                    continue
                raw = raw_value(gen, s, data)
                values[s.name] = [raw, float(raw) * s.factor.double + s.offset.double, True]
            frames.append(values)
        messages.append({"name": m.name, "id": m.can_id, "extended": m.extended, "length": m.dlc,
                         "line": m.line, "cycle_ms": m.cycle_time, "signals": signals, "frames": frames})
    return {"messages": messages}


def first_difference(want, got, where=""):
    if type(want) is not type(got) and not (isinstance(want, (int, float)) and isinstance(got, (int, float))):
        return f"{where}: generator {want!r}, reader {got!r}"
    if isinstance(want, dict):
        for key in sorted(set(want) | set(got)):
            if key not in want or key not in got:
                return f"{where}.{key}: generator {want.get(key, '(absent)')!r}, reader {got.get(key, '(absent)')!r}"
            found = first_difference(want[key], got[key], f"{where}.{key}")
            if found:
                return found
        return None
    if isinstance(want, list):
        if len(want) != len(got):
            return f"{where}: generator has {len(want)} items, reader {len(got)}"
        for index, (a, b) in enumerate(zip(want, got)):
            found = first_difference(a, b, f"{where}[{index}]")
            if found:
                return found
        return None
    if want != got:
        return f"{where}: generator {want!r}, reader {got!r}"
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--generator", required=True)
    parser.add_argument("--dump", required=True)
    parser.add_argument("paths", nargs="+")
    args = parser.parse_args()
    gen = load_generator(args.generator)
    files = []
    for path in args.paths:
        if os.path.isdir(path):
            files += sorted(os.path.join(path, name) for name in os.listdir(path) if name.endswith(".dbc"))
        else:
            files.append(path)
    failures, refused, frames = [], 0, 0
    for path in files:
        want = expected(gen, path)
        out = subprocess.run([args.dump, path, "--frames", str(FRAMES)], capture_output=True, text=True)
        if out.returncode != 0:
            failures.append(f"{path}: dump_dbc exited {out.returncode}: {out.stderr.strip()}")
            continue
        got = json.loads(out.stdout)
        difference = first_difference(want, got)
        if difference:
            failures.append(f"{path}: {difference}")
        elif "error" in want:
            refused += 1
        else:
            frames += sum(len(m["frames"]) for m in want["messages"])
    for failure in failures:
        print(failure)
    print(f"{len(files)} DBC files: {len(files) - len(failures)} read alike ({refused} refused alike, "
          f"{frames} payloads decoded alike), {len(failures)} differ")
    if len(files) < 50:
        print("fewer than 50 files: the corpus is missing")
        return 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
