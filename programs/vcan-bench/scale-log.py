#!/usr/bin/env python3
"""scale-log.py IN OUT FACTOR -- speeds up a candump -L log for canplayer.

Every time stamp "(sec.frac)" becomes t0 + (t - t0) / FACTOR, t0 being the first frame's, so ten
minutes of log with FACTOR 10 play in one. Everything else (interface, frame, other lines, line
ends) is kept byte for byte. Time stamps keep their number of decimals; the arithmetic is exact
(integers and fractions), so a factor of 1 reproduces the input.
"""
import re
import sys
from fractions import Fraction

STAMP = re.compile(rb"^\((\d+)\.(\d+)\)")


def main(argv):
    if len(argv) != 4:
        sys.exit("usage: scale-log.py IN OUT FACTOR")
    src, dst, factor_text = argv[1:]
    try:
        factor = Fraction(factor_text)
    except (ValueError, ZeroDivisionError):
        factor = Fraction(0)
    if factor <= 0:
        sys.exit(f"scale-log: FACTOR must be a positive number, not {factor_text!r}")

    try:
        with open(src, "rb") as f:
            lines = f.readlines()
    except OSError as e:
        sys.exit(f"scale-log: {e}")
    t0 = None
    out = []
    for line in lines:
        m = STAMP.match(line)
        if not m:
            out.append(line)
            continue
        decimals = len(m.group(2))
        t = int(m.group(1)) + Fraction(int(m.group(2)), 10**decimals)
        if t0 is None:
            t0 = t
        scaled = round((t0 + (t - t0) / factor) * 10**decimals)
        stamp = b"(%d.%0*d)" % (scaled // 10**decimals, decimals, scaled % 10**decimals)
        out.append(stamp + line[m.end():])
    try:
        with open(dst, "wb") as f:
            f.writelines(out)
    except OSError as e:
        sys.exit(f"scale-log: {e}")


if __name__ == "__main__":
    main(sys.argv)
