#!/usr/bin/env python3
"""Writes a seed for fuzz_estimator_frames from a candump log (`candump -L`, or `lptn convert`).

    make_estimator_seeds.py --log cycle.log --out seed.bin [--skip-s 300] [--options 0] [--max-bytes 4096]

The record format is the one fuzz_estimator_frames.cpp's header describes; the frames keep their
data and alive counters as logged (kind 0x40), so a real log's converter starts the estimator.
How the seeds in corpus/fuzz_estimator_frames/ were made: `lptn generate --cycles 1 --seed 1`,
`lptn convert` of its cycle, then this script on the log (see corpus/README.md).
"""

import argparse
import re
import struct

# The order of kReceivedIds in the generated lptn/can/lptn_frames.hpp (the DBC's message order).
RECEIVED_IDS = [0x101, 0x102, 0x103, 0x120, 0x130, 0x131]
RECORD = 12
LINE = re.compile(r"\((\d+)\.(\d{6})\) \S+ ([0-9A-Fa-f]{3})#([0-9A-Fa-f]{16})$")


def records(lines, skip_us):
    frames = []
    for line in lines:
        match = LINE.match(line.strip())
        if not match:
            continue  # the estimator's seeds hold classic 8-byte frames only
        t = int(match[1]) * 1_000_000 + int(match[2])
        if t >= skip_us:
            frames.append((t, int(match[3], 16), bytes.fromhex(match[4])))
    for (t, can_id, data), following in zip(frames, frames[1:] + [frames[-1]]):
        selector = RECEIVED_IDS.index(can_id) if can_id in RECEIVED_IDS else 0xF000 | can_id
        delta = min((following[0] - t) // 2000, 0xEF)
        yield struct.pack(">HB8sB", selector, 0x40, data, delta)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--log", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--skip-s", type=float, default=0.0, help="start this far into the log")
    parser.add_argument("--options", type=int, default=0, help="bit 0 open loop, bit 1 float")
    parser.add_argument("--max-bytes", type=int, default=4096, help="the fuzzer's -max_len")
    args = parser.parse_args()
    with open(args.log) as log:
        out = bytes([args.options])
        for record in records(log, int(args.skip_s * 1_000_000)):
            if len(out) + RECORD > args.max_bytes:
                break
            out += record
    with open(args.out, "wb") as seed:
        seed.write(out)


if __name__ == "__main__":
    main()
