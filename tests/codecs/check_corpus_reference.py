#!/usr/bin/env python3
"""Decodes chosen real frames of the corpus through the generated code and holds them to values
worked out by hand from the DBC files' bit layouts (ctest can.corpus.reference).

    check_corpus_reference.py --generator GEN --compiler CXX --corpus DIR --work DIR

cantools is not a Debian package, so the reference is twofold, both independent of the generator:
- CASES: frames whose signal values were computed by hand from the SG_ lines (quoted beside
  each), for multiplexed messages (M / m<N>, SG_MUL_VAL_, a lowercase 'm'), extended ids (the
  0x80000000 flag and a bare 29-bit id) and 64-byte CAN FD frames;
- a model that reads the SG_ lines with its own regular expression and takes each signal from
  the whole frame as one big integer (little-endian for Intel, big-endian for Motorola), applied
  to random frames of the same messages: every signal's raw value, which multiplexed signals the
  frame carries, and the bytes pack() writes back.
The generated code is compiled as the firmware compiles it (-fno-exceptions -fno-rtti, -Werror).
"""

import argparse
import os
import random
import re
import subprocess
import sys

CXX_FLAGS = ["-std=c++20", "-O0", "-fno-exceptions", "-fno-rtti", "-Wall", "-Wextra", "-Wpedantic",
             "-Wshadow", "-Wconversion", "-Wsign-conversion", "-Werror"]

# (file, message, id, extended, length, frame bytes (the rest zero), {signal: raw} for every signal
# the frame carries; multiplexed signals it does not carry must read 0 and not be present)
CASES = [
    # vw_pq Bremse_1: BR1_MSR_Anf M : 1|1@1+, BR1_ASRMo_fa m0 : 40|8@1+, BR1_MSR_Mo_inv m1 : 40|8@1+,
    # and SG_MUL_VAL_ 416 BR1_MSR_Mo_inv BR1_MSR_Anf 1-1. Byte 0 = 0x02: bit 1 set, multiplexor 1.
    ("vw_pq.dbc", "Bremse_1", 0x1A0, False, 8, {0: 0x02, 5: 100},
     {"BR1_MSR_Anf": 1, "BR1_ASR_Anf": 0, "BR1_MSR_Mo_inv": 100}),
    # The same frame with byte 0 = 0x01: BR1_ASR_Anf (0|1) set, multiplexor 0: BR1_ASRMo_fa.
    ("vw_pq.dbc", "Bremse_1", 0x1A0, False, 8, {0: 0x01, 5: 100},
     {"BR1_MSR_Anf": 0, "BR1_ASR_Anf": 1, "BR1_ASRMo_fa": 100}),
    # vw_pq Motor_2: MO2_Mp_Code m : 6|2@1+ (an 'm' without value, read as M), MO2_max_Mo m3 : 0|6@1+.
    # Byte 0 = 0xC5 = 11 000101: multiplexor 3, MO2_max_Mo 5.
    ("vw_pq.dbc", "Motor_2", 0x288, False, 8, {0: 0xC5}, {"MO2_Mp_Code": 3, "MO2_max_Mo": 5}),
    # fca_giorgio NEW_MSG_416: MUX M : 1|2@0+ (byte 0, bits 1..0), UNKNOWN_M0_1 m0 : 15|8@0+ (byte 1),
    # UNKNOWN_M0_2 m0 : 23|8@0+ (byte 2).
    ("fca_giorgio.dbc", "NEW_MSG_416", 0x416, False, 8, {0: 0x00, 1: 0xAB, 2: 0xCD},
     {"MUX": 0, "UNKNOWN_M0_1": 0xAB, "UNKNOWN_M0_2": 0xCD}),
    # vw_mqb VIN_01: VIN_01_MUX M : 0|2@1+, VIN_4/5/6 m1 : 8|8, 16|8, 24|8 (@1+). "WAU" under mux 1.
    ("vw_mqb.dbc", "VIN_01", 0x6B4, False, 8, {0: 0x01, 1: 0x57, 2: 0x41, 3: 0x55},
     {"VIN_01_MUX": 1, "VIN_4": 0x57, "VIN_5": 0x41, "VIN_6": 0x55}),
    # tesla_can UI_driverAssistRoadSign: UI_roadSign M : 0|8@1+; under 1, UI_stopSignStopLineDist
    # m1 : 8|10@1+ = 0x28 | (0xC9 & 3) << 8 = 296, UI_stopSignStopLineConf m1 : 18|7@1+ = 0xC9 >> 2 = 50.
    ("tesla_can.dbc", "UI_driverAssistRoadSign", 0x238, False, 8, {0: 0x01, 1: 0x28, 2: 0xC9},
     {"UI_roadSign": 1, "UI_stopSignStopLineDist": 296, "UI_stopSignStopLineConf": 50}),
    # gm_global_a_lowspeed DriverDoorStatus: BO_ 274923520 (0x10630000, no flag: taken as extended),
    # DriverDoorOpened : 0|1@0+ (bit 0 of byte 0).
    ("gm_global_a_lowspeed.dbc", "DriverDoorStatus", 0x10630000, True, 1, {0: 0x01}, {"DriverDoorOpened": 1}),
    # vw_mqb KN_Airbag_01: BO_ 2549088277 = 0x80000000 | 0x17F00015. Airbag_01_KompSchutz : 0|1@1+,
    # Airbag_01_Nachlauftyp : 4|4@1+ (byte 0 high nibble), AB_KD_Fehler : 63|1@1+ (byte 7, bit 7).
    ("vw_mqb.dbc", "KN_Airbag_01", 0x17F00015, True, 8, {0: 0xA1, 7: 0x80},
     {"Airbag_01_KompSchutz": 1, "Airbag_01_Nachlauftyp": 10, "AB_KD_Fehler": 1}),
    # gwm_haval_h6_phev_2024 CAR_OVERALL_SIGNALS2, 64 bytes: CRC1 : 7|8@0+ (byte 0), COUNTER1 :
    # 59|4@0+ (byte 7, bits 3..0), REQ_REVIEW_POWER_STATE_SIGNAL : 302|4@0+ (byte 37, bits 6..3:
    # 0x68 = 0 1101 000 -> 13).
    ("gwm_haval_h6_phev_2024.dbc", "CAR_OVERALL_SIGNALS2", 0x60, False, 64, {0: 0x5A, 7: 0x0C, 37: 0x68},
     {"CRC1": 0x5A, "COUNTER1": 12, "REQ_REVIEW_POWER_STATE_SIGNAL": 13}),
    # FORD_CADS_64 MRR_Detection_004, 64 bytes: CAN_DET_RANGE_04_01 : 31|14@0+ = byte 3 (8 bits) then
    # byte 4 bits 7..2: 0x12 << 6 | 0x34 >> 2 = 1165; CAN_DET_VALID_LEVEL_04_01 : 0|1@0+ (byte 0 bit 0).
    ("FORD_CADS_64.dbc", "MRR_Detection_004", 0x123, False, 64, {0: 0x01, 3: 0x12, 4: 0x34},
     {"CAN_DET_RANGE_04_01": 1165, "CAN_DET_VALID_LEVEL_04_01": 1}),
]

# Messages the model checks on random frames (the CASES' messages and a few more).
MODEL_MESSAGES = sorted({(case[0], case[1]) for case in CASES} | {
    ("vw_pq.dbc", "Motor_3"),  # SG_MUL_VAL_ 896 MO3_FPGradient MO3_Sta_FPG 1-1
    ("vw_mqbevo.dbc", "VIN_01"),
    ("tesla_model3_party.dbc", "VCFRONT_LVPowerState"),
    ("gm_global_a_lowspeed_1818125.dbc", "ODI_CenterStack_2_BCM_LS"),  # the extended flag
})
RANDOM_FRAMES = 64


# ---------------------------------------------------------------------------------------------
# The model: the DBC's own text, read here with nothing from the generator.

SG = re.compile(r"^\s*SG_\s+(\w+)\s*(M|m\d*M?)?\s*:\s*(\d+)\|(\d+)@([01])([+-])")


def read_message(path, name):
    """(id as written, [(signal, start, length, big_endian, signed, mux)]), mux None, 'M' or a set."""
    lines = open(path, "rb").read().decode("latin-1").splitlines()
    for index, line in enumerate(lines):
        match = re.match(r"^BO_\s+(\d+)\s+(\w+)\s*:", line)
        if match and match.group(2) == name:
            dbc_id, signals = int(match.group(1)), []
            for body in lines[index + 1:]:
                sg = SG.match(body)
                if not sg:
                    break
                indicator = sg.group(2)
                mux = None
                if indicator in ("M", "m"):
                    mux = "M"
                elif indicator:
                    mux = {int(indicator[1:])}
                signals.append((sg.group(1), int(sg.group(3)), int(sg.group(4)), sg.group(5) == "0",
                                sg.group(6) == "-", mux))
            for line2 in lines:
                mul = re.match(rf"^SG_MUL_VAL_\s+{dbc_id}\s+(\w+)\s+\w+\s+(.*);", line2)
                if mul:
                    values = set()
                    for low, high in re.findall(r"(\d+)-(\d+)", mul.group(2)):
                        values |= set(range(int(low), int(high) + 1))
                    signals = [s[:5] + (values,) if s[0] == mul.group(1) else s for s in signals]
            return dbc_id, signals
    raise SystemExit(f"{path}: no message {name}")


def field(length_bytes, start, length, big_endian):
    """(shift, mask) of the signal in the frame read as one integer (big- or little-endian)."""
    if not big_endian:
        return start, (1 << length) - 1
    msb_on_wire = 8 * (start // 8) + 7 - start % 8
    return 8 * length_bytes - msb_on_wire - length, (1 << length) - 1


def model_decode(frame, signals):
    """{signal: raw} of the signals the frame carries, and the frame pack() should write back."""
    size = len(frame)
    words = {False: int.from_bytes(frame, "little"), True: int.from_bytes(frame, "big")}
    raw, packed = {}, {False: 0, True: 0}
    mux_value = None
    for name, start, length, big_endian, signed, mux in signals:
        if mux == "M":
            shift, mask = field(size, start, length, big_endian)
            mux_value = words[big_endian] >> shift & mask
    for name, start, length, big_endian, signed, mux in signals:
        if mux not in (None, "M") and mux_value not in mux:
            continue
        shift, mask = field(size, start, length, big_endian)
        bits = words[big_endian] >> shift & mask
        packed[big_endian] |= bits << shift
        raw[name] = bits - (1 << length) if signed and bits >> (length - 1) else bits
    back = bytes(a | b for a, b in zip(packed[False].to_bytes(size, "little"), packed[True].to_bytes(size, "big")))
    return raw, back


# ---------------------------------------------------------------------------------------------
# The generated code

def generate(args, dbc):
    safe = re.sub(r"\W", "_", os.path.splitext(dbc)[0])
    out = os.path.join(args.work, "include", "reference", f"{safe}.hpp")
    path = os.path.join(args.corpus, dbc)
    result = subprocess.run([args.generator, "--dbc", path, "--node", "Vector__XXX",
                             "--namespace", f"reference::{safe}", "--out", out],
                            capture_output=True, text=True, check=False)
    if result.returncode != 0:
        raise SystemExit(f"the generator refused {dbc}: {result.stderr}")
    return f"reference/{safe}.hpp", f"reference::{safe}", open(out, encoding="ascii").read()


def struct_of(header_text, message):
    """The struct generated for a message: its name, members in DBC order, and which are multiplexed."""
    match = next((block for block in re.finditer(r"^struct (\w+) \{\n(.*?)^\};", header_text, re.M | re.S)
                  if f'kName = "{message}";' in block.group(2)), None)
    if not match:
        raise SystemExit(f"no struct for message {message}")
    body = match.group(2)
    members = re.findall(r"^  std::u?int\d+_t (\w+) = 0;  // .*?(, in the frame when .*)?$", body, re.M)
    names = re.findall(r'^      \{"([^"]*)", ', body, re.M)
    present = re.findall(r"^  constexpr bool (\w+_is_present)\(\)", body, re.M)
    muxed = iter(present)
    return match.group(1), [(name, member, next(muxed) if when else None)
                            for name, (member, when) in zip(names, members)]


def program(jobs):
    """jobs: [(include, namespace, struct, members, frame bytes)] -> C++ printing, per job, each
    signal `name raw present` and the frame pack() writes back."""
    includes = sorted({job[0] for job in jobs})
    body = []
    for index, (_, namespace, struct, members, frame) in enumerate(jobs):
        data = ", ".join(str(byte) for byte in frame)
        body.append("  {")
        body.append(f"    const std::uint8_t frame[{len(frame)}] = {{{data}}};")
        body.append(f"    {namespace}::{struct} m{{}};")
        body.append(f'    std::printf("job {index} id %lx ext %d len %u unpack %d\\n", '
                    f"static_cast<unsigned long>(m.kId), m.kExtended ? 1 : 0, static_cast<unsigned>(m.kLength), "
                    f"m.unpack(frame, sizeof frame) ? 1 : 0);")
        for name, member, present in members:
            flag = f"m.{present}() ? 1 : 0" if present else "1"
            body.append(f'    show("{name}", m.{member}, {flag});')
        body.append(f"    std::uint8_t back[{len(frame)}]{{}};")
        body.append("    m.pack(back, sizeof back);")
        body.append('    std::printf("pack");')
        body.append('    for (const auto byte : back) std::printf(" %02x", static_cast<unsigned>(byte));')
        body.append('    std::printf("\\n");')
        body.append("  }")
    show = """
template <typename Raw>
void show(const char* name, Raw raw, int present) {
  if constexpr (std::is_signed_v<Raw>) {
    std::printf("%s %lld %d\\n", name, static_cast<long long>(raw), present);
  } else {
    std::printf("%s %llu %d\\n", name, static_cast<unsigned long long>(raw), present);
  }
}
"""
    return ("#include <cstdint>\n#include <cstdio>\n#include <type_traits>\n\n"
            + "".join(f'#include "{inc}"\n' for inc in includes) + show
            + "\nint main() {\n" + "\n".join(body) + "\n  return 0;\n}\n")


def run_jobs(args, jobs):
    source = os.path.join(args.work, "reference.cpp")
    with open(source, "w", encoding="ascii") as file:
        file.write(program(jobs))
    binary = os.path.join(args.work, "reference")
    compiled = subprocess.run([args.compiler, *CXX_FLAGS, "-I", os.path.join(args.work, "include"), source, "-o",
                               binary], capture_output=True, text=True, check=False)
    if compiled.returncode != 0:
        raise SystemExit(f"the reference program does not compile:\n{compiled.stderr[:6000]}")
    output = subprocess.run([*args.emulator.split(), binary], capture_output=True, text=True, check=True).stdout
    results = []
    for block in re.split(r"^job \d+ ", output, flags=re.M)[1:]:
        head, *lines = block.strip().splitlines()
        values = {}
        for line in lines[:-1]:
            name, raw, present = line.split()
            values[name] = (int(raw), present == "1")
        results.append((head, values, bytes(int(byte, 16) for byte in lines[-1].split()[1:])))
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--generator", required=True)
    parser.add_argument("--compiler", required=True)
    parser.add_argument("--corpus", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--emulator", default="",
                        help="what runs the compiled programs, e.g. 'qemu-aarch64-static -L /usr/aarch64-linux-gnu' (cross builds)")
    args = parser.parse_args()
    os.makedirs(os.path.join(args.work, "include", "reference"), exist_ok=True)
    headers = {dbc: generate(args, dbc) for dbc in sorted({dbc for dbc, _ in MODEL_MESSAGES})}
    rng = random.Random(20260822)
    jobs, checks = [], []
    for dbc, message, can_id, extended, length, data, expected in CASES:
        include, namespace, text = headers[dbc]
        struct, members = struct_of(text, message)
        frame = bytes(data.get(i, 0) for i in range(length))
        jobs.append((include, namespace, struct, members, frame))
        checks.append(("hand", dbc, message, can_id, extended, frame, expected, members))
    for dbc, message in MODEL_MESSAGES:
        include, namespace, text = headers[dbc]
        struct, members = struct_of(text, message)
        dbc_id, signals = read_message(os.path.join(args.corpus, dbc), message)
        length = int(re.search(r"kLength = (\d+);", text[text.index(f"struct {struct} {{"):]).group(1))
        for _ in range(RANDOM_FRAMES):
            frame = bytes(rng.randrange(256) for _ in range(length))
            jobs.append((include, namespace, struct, members, frame))
            checks.append(("model", dbc, message, None, None, frame, signals, members))
    problems = []
    for check, (head, values, back) in zip(checks, run_jobs(args, jobs)):
        kind, dbc, message, can_id, extended, frame, expected, members = check
        where = f"{dbc} {message} frame {frame.hex()}"
        if not head.endswith("unpack 1"):
            problems.append(f"{where}: unpack failed ({head})")
        if kind == "hand":
            if head.split()[:4] != ["id", f"{can_id:x}", "ext", str(int(extended))]:
                problems.append(f"{where}: {head}, expected id {can_id:x} extended {extended}")
            for name, member, present in members:
                want = expected.get(name)
                got_raw, got_present = values[name]
                if want is None and got_raw != 0:  # absent, or its bits are 0 in the frame
                    problems.append(f"{where}: {name} should read 0, reads {got_raw} present={got_present}")
                if want is not None and (got_raw != want or not got_present):
                    problems.append(f"{where}: {name} reads {got_raw} (present={got_present}), by hand {want}")
            missing = set(expected) - {name for name, _, _ in members}
            if missing:
                problems.append(f"{where}: no such signals {sorted(missing)}")
        else:
            raw, packed = model_decode(frame, expected)
            for name, member, present in members:
                got_raw, got_present = values[name]
                if name in raw and (got_raw != raw[name] or not got_present):
                    problems.append(f"{where}: {name} reads {got_raw} (present={got_present}), model {raw[name]}")
                if name not in raw and (got_raw != 0 or got_present):
                    problems.append(f"{where}: {name} is not in the frame but reads {got_raw} present={got_present}")
            if back != packed:
                problems.append(f"{where}: pack() wrote {back.hex()}, model {packed.hex()}")
    hand = sum(1 for check in checks if check[0] == "hand")
    print(f"{hand} hand-computed frames and {len(checks) - hand} random frames of {len(MODEL_MESSAGES)} messages "
          f"({', '.join(f'{d}:{m}' for d, m in MODEL_MESSAGES)})")
    for problem in problems[:50]:
        print(f"FAILED: {problem}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
