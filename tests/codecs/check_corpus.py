#!/usr/bin/env python3
"""Runs the DBC codecs generator (lptn-dbc-codegen) over the real DBC files in tests/codecs/corpus/ and
compiles what it writes (ctest can.corpus).

    check_corpus.py --generator GEN --compiler CXX --corpus DIR --work DIR [--jobs N]

For every corpus/*.dbc: the generator must accept it (warnings allowed; --node Vector__XXX, a header
for the whole bus), and a small C++ program
that includes the header must compile as the firmware compiles the headers (-fno-exceptions
-fno-rtti, the project's warnings and -Werror) and run: every message unpacks 64 bytes of noise
(several patterns, so that multiplexors take several values), packs what it read, and unpacking
and packing again must give the same bytes. The report gives how many files were accepted, the
warnings by kind, and any file that was refused or whose header failed.
"""

import argparse
import collections
import concurrent.futures
import os
import re
import subprocess
import sys

CXX_FLAGS = ["-std=c++20", "-O0", "-fno-exceptions", "-fno-rtti", "-Wall", "-Wextra", "-Wpedantic",
             "-Wshadow", "-Wconversion", "-Wsign-conversion", "-Werror"]

# Warning kinds, by what the generator's warning says (the first that matches).
KINDS = [
    ("range does not fit the raw bits", r"bits cannot represent them"),
    ("range contains no raw value", r"contains no raw value"),
    ("minimum greater than maximum", r"is greater than maximum"),
    ("overlapping signals", r"overlaps signal"),
    ("signal overflows its frame (left out)", r"overflows its"),
    ("message without signals", r"has no signals"),
    ("node not in BU_", r"is not a node in BU_"),
    ("node listed twice in BU_", r"is listed twice in BU_"),
    ("no BU_ section", r"has no BU_ section"),
    ("bare id above 0x7FF taken as extended", r"taken as a 29-bit extended id"),
    ("id fits no CAN frame (message left out)", r"no CAN frame has it"),
    ("not a CAN FD length", r"is not a CAN FD frame length"),
    ("missing ';'", r"expected ';'"),
    ("'m' read as multiplexor 'M'", r"multiplex indicator 'm' without a value"),
    ("multiplexor never takes the value", r"never takes"),
    ("reference to an undefined message or signal", r"no message has id|has no signal"),
    ("VAL_ value outside the signal", r"VAL_ value .* does not fit"),
    ("statement given twice (later used)", r"^second "),
    ("C++ name clash (renamed)", r"clashes with"),
]


def kind_of(reason):
    return next((kind for kind, pattern in KINDS if re.search(pattern, reason)), "other")


def program(header, namespace, structs):
    calls = "\n".join(f"  failures += exercise<{namespace}::{struct}>(noise);" for struct in structs)
    return f"""// Written by check_corpus.py: every message of {header} through unpack and pack.
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "{header}"

namespace {{

std::uint8_t noise[64];

template <typename Message>
int exercise(const std::uint8_t* frame) {{
  int failures = 0;
  for (unsigned pattern = 0; pattern < 16; ++pattern) {{
    std::uint8_t bytes[64];
    for (std::size_t i = 0; i < sizeof bytes; ++i) {{
      bytes[i] = static_cast<std::uint8_t>(frame[i] * (pattern + 1) + pattern * 37u);
    }}
    Message first{{}};
    std::uint8_t once[64]{{}};
    std::uint8_t twice[64]{{}};
    Message second{{}};
    bool ok = first.unpack(bytes, Message::kLength) && first.pack(once, sizeof once) &&
              second.unpack(once, Message::kLength) && second.pack(twice, Message::kLength);
    for (std::size_t i = 0; i < sizeof once; ++i) {{
      ok = ok && once[i] == twice[i] && (i < Message::kLength || once[i] == 0);
    }}
    // A buffer shorter than the frame is refused.
    ok = ok && (Message::kLength == 0 || !first.unpack(bytes, Message::kLength - 1u));
    if (!ok) {{
      std::printf("%s: pack/unpack are not consistent (pattern %u)\\n", Message::kName, pattern);
      ++failures;
    }}
  }}
  return failures;
}}

}}  // namespace

int main() {{
  std::uint32_t state = 12345;
  for (auto& byte : noise) {{
    state = state * 1103515245u + 12345u;
    byte = static_cast<std::uint8_t>(state >> 16);
  }}
  int failures = 0;
{calls}
  return failures == 0 ? 0 : 1;
}}
"""


def check_file(dbc, args):
    """(warnings [(line, reason)], problem or None, number of messages)"""
    name = os.path.splitext(os.path.basename(dbc))[0]
    safe = re.sub(r"\W", "_", name)
    namespace = f"corpus::{safe}"
    header = f"corpus/{safe}.hpp"
    include_dir = os.path.join(args.work, "include")
    out = os.path.join(include_dir, header)
    # Vector__XXX: a header for the whole bus, as a logger would have it (no node's ids listed).
    result = subprocess.run([args.generator, "--dbc", dbc, "--node", "Vector__XXX",
                             "--namespace", namespace, "--out", out], capture_output=True, text=True, check=False)
    warnings = []
    for line in result.stderr.splitlines():
        match = re.match(r".*?:(\d+): warning: (.*)$", line)
        if match:
            warnings.append((int(match.group(1)), match.group(2)))
    if result.returncode != 0:
        return warnings, f"refused: {result.stderr.strip()}", 0
    with open(out, encoding="ascii") as file:
        structs = re.findall(r"^struct (\w+) \{$", file.read(), re.M)
    source = os.path.join(args.work, f"{safe}.cpp")
    with open(source, "w", encoding="ascii") as file:
        file.write(program(header, namespace, structs))
    binary = os.path.join(args.work, safe)
    compiled = subprocess.run([args.compiler, *CXX_FLAGS, "-I", include_dir, source, "-o", binary],
                              capture_output=True, text=True, check=False)
    if compiled.returncode != 0:
        return warnings, f"the header does not compile:\n{compiled.stderr[:4000]}", len(structs)
    ran = subprocess.run([*args.emulator.split(), binary], capture_output=True, text=True, check=False)
    if ran.returncode != 0:
        return warnings, f"the program failed:\n{ran.stdout[:4000]}", len(structs)
    return warnings, None, len(structs)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--generator", required=True)
    parser.add_argument("--compiler", required=True)
    parser.add_argument("--corpus", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--emulator", default="",
                        help="what runs the compiled programs, e.g. 'qemu-aarch64-static -L /usr/aarch64-linux-gnu' (cross builds)")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--verbose", action="store_true", help="print every warning")
    args = parser.parse_args()
    os.makedirs(os.path.join(args.work, "include", "corpus"), exist_ok=True)
    files = sorted(os.path.join(args.corpus, name) for name in os.listdir(args.corpus) if name.endswith(".dbc"))
    if not files:
        sys.exit(f"no .dbc files in {args.corpus}")
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = list(pool.map(lambda dbc: check_file(dbc, args), files))

    kinds = collections.Counter()
    files_by_kind = collections.defaultdict(set)
    accepted, problems, messages = 0, [], 0
    for dbc, (warnings, problem, count) in zip(files, results):
        name = os.path.basename(dbc)
        messages += count
        if problem is None or not problem.startswith("refused"):
            accepted += 1
        if problem:
            problems.append(f"{name}: {problem}")
        for line, reason in warnings:
            kinds[kind_of(reason)] += 1
            files_by_kind[kind_of(reason)].add(name)
            if args.verbose:
                print(f"{name}:{line}: warning: {reason}")
    print(f"{accepted} of {len(files)} corpus files accepted by the generator; {messages} message structs "
          f"compiled and exercised")
    print(f"warnings by kind ({sum(kinds.values())} in all):")
    for kind, count in kinds.most_common():
        print(f"  {count:5d}  {kind}  ({len(files_by_kind[kind])} files)")
    for problem in problems:
        print(f"FAILED: {problem}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
