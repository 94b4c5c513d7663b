#!/usr/bin/env python3
"""Runs the DBC codecs generator (lptn-dbc-codegen, can/codegen) as the build does and checks what it
did (ctest, label can).

    check_generator.py rejects GENERATOR DBC LINE REASON
        exit status 1, stderr exactly one line "DBC:LINE: ..." that contains REASON, nothing on
        stdout, and no file written (not even a temporary one)
    check_generator.py warns GENERATOR DBC LINE REASON
        exit status 0 and a header written, stderr exactly one line "DBC:LINE: warning: ..." that
        contains REASON; and with --werror, what `rejects` checks, the line without "warning: "
    check_generator.py accepts GENERATOR DBC
        exit status 0, a header written, nothing on stderr (node LPTN)
    check_generator.py deterministic GENERATOR DBC NODE
        two runs write the same bytes
    check_generator.py encoding GENERATOR DBC NODE
        the DBC saved as Latin-1 with CRLF line ends (as Windows tools write it) gives the same
        header as the UTF-8, LF original
"""

import os
import subprocess
import sys
import tempfile


def run(generator, dbc, node, out_dir, *extra):
    out = os.path.join(out_dir, "lptn", "can", "frames.hpp")
    result = subprocess.run(
        [generator, "--dbc", dbc, "--node", node, "--namespace", "lptn::can", "--out", out, *extra],
        capture_output=True, text=True, check=False)
    return result, out


def generated_bytes(generator, dbc, node):
    with tempfile.TemporaryDirectory() as out_dir:
        result, out = run(generator, dbc, node, out_dir)
        if result.returncode != 0:
            sys.exit(f"the generator failed on {dbc}: {result.stderr}")
        with open(out, "rb") as file:
            return file.read()


def rejects(generator, dbc, line, reason, *extra):
    with tempfile.TemporaryDirectory() as out_dir:
        result, _ = run(generator, dbc, "LPTN", out_dir, *extra)
        left_behind = [os.path.join(root, name) for root, dirs, files in os.walk(out_dir) for name in dirs + files]
    problems = []
    if result.returncode != 1:
        problems.append(f"exit status {result.returncode}, expected 1")
    if result.stdout:
        problems.append(f"stdout is not empty: {result.stdout!r}")
    lines = result.stderr.splitlines()
    prefix = f"{dbc}:{line}: "
    if len(lines) != 1:
        problems.append(f"stderr has {len(lines)} lines, expected 1")
    elif not lines[0].startswith(prefix) or reason not in lines[0][len(prefix):]:
        problems.append(f"stderr does not start with {prefix!r} and then say {reason!r}")
    if left_behind:
        problems.append(f"files were written: {left_behind}")
    print(f"stderr: {result.stderr.rstrip()}")
    return problems


def warns(generator, dbc, line, reason):
    with tempfile.TemporaryDirectory() as out_dir:
        result, out = run(generator, dbc, "LPTN", out_dir)
        written = os.path.isfile(out)
    problems = []
    if result.returncode != 0:
        problems.append(f"exit status {result.returncode}, expected 0")
    if not written:
        problems.append("no header was written")
    if result.stdout:
        problems.append(f"stdout is not empty: {result.stdout!r}")
    lines = result.stderr.splitlines()
    prefix = f"{dbc}:{line}: warning: "
    if len(lines) != 1:
        problems.append(f"stderr has {len(lines)} lines, expected 1")
    elif not lines[0].startswith(prefix) or reason not in lines[0][len(prefix):]:
        problems.append(f"stderr does not start with {prefix!r} and then say {reason!r}")
    print(f"stderr: {result.stderr.rstrip()}")
    print("with --werror:")
    return problems + [f"--werror: {problem}" for problem in rejects(generator, dbc, line, reason, "--werror")]


def accepts(generator, dbc):
    with tempfile.TemporaryDirectory() as out_dir:
        result, out = run(generator, dbc, "LPTN", out_dir, "--werror")
        written = os.path.isfile(out)
    problems = []
    if result.returncode != 0 or not written:
        problems.append(f"exit status {result.returncode}, no header written" if not written
                        else f"exit status {result.returncode}")
    if result.stdout or result.stderr:
        problems.append(f"output: {result.stdout!r} {result.stderr!r}")
    return problems


def deterministic(generator, dbc, node):
    first, second = generated_bytes(generator, dbc, node), generated_bytes(generator, dbc, node)
    return [] if first == second else ["two runs wrote different headers"]


def encoding(generator, dbc, node):
    with open(dbc, encoding="utf-8") as file:
        text = file.read()
    with tempfile.TemporaryDirectory() as directory:
        windows_dbc = os.path.join(directory, os.path.basename(dbc))  # same name: the header quotes it
        with open(windows_dbc, "w", encoding="latin-1", newline="\r\n") as file:
            file.write(text)
        windows = generated_bytes(generator, windows_dbc, node)
    same = windows == generated_bytes(generator, dbc, node)
    return [] if same else ["the Latin-1/CRLF copy gives a different header"]


def main(argv):
    checks = {"rejects": (rejects, 4), "warns": (warns, 4), "accepts": (accepts, 2),
              "deterministic": (deterministic, 3), "encoding": (encoding, 3)}
    if len(argv) < 2 or argv[1] not in checks or len(argv) - 2 != checks[argv[1]][1]:
        sys.exit(__doc__)
    check, _ = checks[argv[1]]
    problems = check(*argv[2:])
    for problem in problems:
        print(f"FAILED: {problem}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
