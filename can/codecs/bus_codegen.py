#!/usr/bin/env python3
"""Generates the firmware's glue to a converter's bus from a bus map (bus.toml).

    bus_codegen.py --bus bus.toml --codecs lptn/bus/converter_frames.hpp --codec-namespace NS
                   --namespace lptn::bus --out DIR/lptn/bus/bus_glue.hpp
    bus_codegen.py --bus bus.toml --print-dbc        the map's DBC file (for the build's dependencies)
    bus_codegen.py --vocabulary --out DIR/lptn/bus/bus_vocabulary.hpp

The map names, per estimator input, the converter's message and signal that carry it, and per
message its alive counter; the DBC it names gives the bits. The glue decodes a frame into a
fw::BusReading through the codecs dbc_codegen.py generated from that DBC: no DBC parsing on the
target. `lptn replay --bus` reads the same map at run time (can/bus); the two must agree, and a
test holds them equal on one log.

A map that names a message or signal the DBC lacks, an unknown input, or a signal whose unit cannot
be the input's stops the build: one line `FILE:LINE: reason` naming the key, exit status 1, and no
output file.

Python 3.11 standard library only: the build host may have nothing else.
"""

import argparse
import os
import re
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bus_vocabulary  # noqa: E402
import dbc_codegen  # noqa: E402

GENERATOR = "can/codecs/bus_codegen.py"
INPUT_KEYS = {"message", "signal", "scale", "offset"}
MESSAGE_KEYS = {"alive_counter", "max_delta_counter", "crc", "data_id", "cycle_ms"}
MESSAGE_KEY_LIST = "alive_counter, max_delta_counter, crc, data_id, cycle_ms"
TOP_KEYS = {"dbc", "inputs", "messages", "outputs"}
# The estimator's own frames, whose default ids a map's [outputs] may change.
LPTN_DBC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "lptn.dbc")


class MapError(Exception):
    def __init__(self, line, reason):
        super().__init__(reason)
        self.line = line
        self.reason = reason


class Lines:
    """Where a table or key of the map is written: tomllib keeps no positions."""

    def __init__(self, text):
        self.tables = {}  # "inputs.speed_rpm" -> line
        self.keys = {}  # ("inputs.speed_rpm", "signal") -> line
        table = ""
        for number, raw in enumerate(text.splitlines(), 1):
            line = raw.split("#", 1)[0].strip()
            header = re.fullmatch(r"\[\s*([^\[\]]+?)\s*\]", line)
            if header:
                table = ".".join(part.strip().strip('"') for part in header.group(1).split("."))
                self.tables.setdefault(table, number)
                continue
            key = re.match(r'("?)([A-Za-z0-9_.-]+)\1\s*=', line)
            if key:
                self.keys.setdefault((table, key.group(2)), number)

    def of(self, table, key=None):
        if key is not None and (table, key) in self.keys:
            return self.keys[(table, key)]
        return self.tables.get(table, 1)


class Input:
    def __init__(self, column, enumerator, message, signal, scale, offset):
        self.column, self.enumerator = column, enumerator
        self.message, self.signal = message, signal
        self.scale, self.offset = scale, offset


class MessageUse:
    def __init__(self, message):
        self.message = message
        self.inputs = []
        self.counter = None
        self.max_delta = bus_vocabulary.DEFAULT_MAX_DELTA_COUNTER
        self.crc = None
        self.crc_byte = 0
        self.data_id = 0
        self.cycle_ms = message.cycle_time or 0


def _number(value, table, key, lines):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise MapError(lines.of(table, key), f"{key} must be a number")
    return float(value)


def _string(value, table, key, lines):
    if not isinstance(value, str) or not value:
        raise MapError(lines.of(table, key), f"{key} must be a non-empty string")
    return value


def read_map(path):
    """The map and its DBC, checked: (dbc path, Dbc, [MessageUse] in the DBC's order)."""
    text = open(path, encoding="utf-8").read()
    lines = Lines(text)
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        match = re.search(r"line (\d+)", str(error))
        raise MapError(int(match.group(1)) if match else 1, f"not TOML: {error}")
    for key in document:
        if key not in TOP_KEYS:
            raise MapError(lines.of("", key) if ("", key) in lines.keys else lines.of(key),
                           f"unknown key '{key}' (dbc, [inputs.NAME], [messages.NAME], [outputs])")
    if "dbc" not in document:
        raise MapError(1, "dbc = \"converter.dbc\" is missing")
    dbc_path = os.path.join(os.path.dirname(os.path.abspath(path)), _string(document["dbc"], "", "dbc", lines))
    try:
        dbc_text = dbc_codegen.read_text(dbc_path)
    except OSError as error:
        raise MapError(lines.of("", "dbc"), f"dbc: cannot read {dbc_path} ({error.strerror})")
    warnings = dbc_codegen.Warnings()
    try:
        dbc = dbc_codegen.Parser(dbc_codegen.tokenize(dbc_text), warnings).parse()
        # As the codecs are generated (--node Vector__XXX): a signal outside its frame is left out.
        dbc_codegen.Checker(dbc, warnings, dbc_codegen.NO_NODE).run()
    except dbc_codegen.DbcError as error:
        raise MapError(lines.of("", "dbc"), f"dbc: {dbc_path}:{error.line}: {error.reason}")
    messages = {m.name: m for m in dbc.messages if m.generated}

    words = {column: (enumerator, required, unit) for column, enumerator, required, unit in bus_vocabulary.INPUTS}
    uses = {}
    inputs = document.get("inputs", {})
    if not isinstance(inputs, dict):
        raise MapError(lines.of("", "inputs"), "inputs must be tables [inputs.NAME]")
    for column, entry in inputs.items():
        table = f"inputs.{column}"
        if column not in words:
            raise MapError(lines.of(table), f"[{table}]: unknown input '{column}' (one of {', '.join(words)})")
        if not isinstance(entry, dict):
            raise MapError(lines.of(table), f"[{table}] must be a table")
        for key in entry:
            if key not in INPUT_KEYS:
                raise MapError(lines.of(table, key), f"[{table}]: unknown key '{key}' (message, signal, scale, offset)")
        for key in ("message", "signal"):
            if key not in entry:
                raise MapError(lines.of(table), f"[{table}]: {key} is missing")
        name = _string(entry["message"], table, "message", lines)
        if name not in messages:
            raise MapError(lines.of(table, "message"), f"[{table}] message: {name} is not a message of {os.path.basename(dbc_path)}")
        message = messages[name]
        signal_name = _string(entry["signal"], table, "signal", lines)
        signal = next((s for s in message.signals if s.name == signal_name), None)
        if signal is None or signal in message.left_out_signals:
            raise MapError(lines.of(table, "signal"), f"[{table}] signal: {name} has no signal {signal_name}")
        if signal.multiplexor:
            raise MapError(lines.of(table, "signal"), f"[{table}] signal: {signal_name} is {name}'s multiplexor")
        scale = _number(entry.get("scale", 1.0), table, "scale", lines)
        offset = _number(entry.get("offset", 0.0), table, "offset", lines)
        if scale == 0.0:
            raise MapError(lines.of(table, "scale"), f"[{table}] scale: 0 would make the input a constant")
        enumerator, _, unit = words[column]
        problem = bus_vocabulary.unit_problem(signal.unit, unit, scale, offset)
        if problem:
            raise MapError(lines.of(table, "signal"), f"[{table}] signal: {name}.{signal_name} cannot be {column}: {problem}")
        if signal.unit.strip() not in bus_vocabulary.UNITS:
            print(f"{path}:{lines.of(table, 'signal')}: warning: [{table}]: {name}.{signal_name}'s unit "
                  f"'{signal.unit}' is not one lptn knows; taken as {unit} times scale plus offset", file=sys.stderr)
        use = uses.setdefault(name, MessageUse(message))
        use.inputs.append(Input(column, enumerator, message, signal, scale, offset))
    for column, (_, required, _) in words.items():
        if required and column not in inputs:
            raise MapError(1, f"[inputs.{column}] is missing: the estimator cannot run without it")

    extra = document.get("messages", {})
    if not isinstance(extra, dict):
        raise MapError(lines.of("", "messages"), "messages must be tables [messages.NAME]")
    for name, entry in extra.items():
        table = f"messages.{name}"
        if name not in uses:
            raise MapError(lines.of(table), f"[{table}]: {name} carries no input of this map")
        for key in entry:
            if key not in MESSAGE_KEYS:
                raise MapError(lines.of(table, key), f"[{table}]: unknown key '{key}' ({MESSAGE_KEY_LIST})")
        use = uses[name]
        if "alive_counter" in entry:
            counter = _string(entry["alive_counter"], table, "alive_counter", lines)
            signal = next((s for s in use.message.signals if s.name == counter), None)
            if signal is None:
                raise MapError(lines.of(table, "alive_counter"), f"[{table}] alive_counter: {name} has no signal {counter}")
            if signal.multiplexed or signal.signed or signal.length > 8 or signal.factor.value != 1 or signal.offset.value != 0:
                raise MapError(lines.of(table, "alive_counter"),
                               f"[{table}] alive_counter: {counter} is no counter (unsigned, 1 to 8 bits, factor 1, "
                               f"offset 0, in every frame)")
            use.counter = signal
        if "max_delta_counter" in entry:
            delta = entry["max_delta_counter"]
            if "alive_counter" not in entry:
                raise MapError(lines.of(table, "max_delta_counter"), f"[{table}] max_delta_counter: there is no alive_counter")
            if isinstance(delta, bool) or not isinstance(delta, int) or not 1 <= delta < (1 << use.counter.length):
                raise MapError(lines.of(table, "max_delta_counter"),
                               f"[{table}] max_delta_counter: a whole number from 1 to {(1 << use.counter.length) - 1}")
            use.max_delta = delta
        if "crc" in entry:
            crc = _string(entry["crc"], table, "crc", lines)
            signal = next((s for s in use.message.signals if s.name == crc), None)
            if signal is None:
                raise MapError(lines.of(table, "crc"), f"[{table}] crc: {name} has no signal {crc}")
            aligned = signal.start % 8 == (7 if signal.big_endian else 0)
            if (signal.multiplexed or signal.signed or signal.length != 8 or not aligned or signal.factor.value != 1
                    or signal.offset.value != 0):
                raise MapError(lines.of(table, "crc"),
                               f"[{table}] crc: {crc} is no CRC-8 (unsigned, 8 bits, one whole byte, factor 1, offset 0, "
                               f"in every frame)")
            if "data_id" not in entry:
                raise MapError(lines.of(table, "crc"), f"[{table}] crc: data_id (0..65535) is missing")
            use.crc, use.crc_byte = signal, signal.start // 8
        if "data_id" in entry:
            data_id = entry["data_id"]
            if "crc" not in entry:
                raise MapError(lines.of(table, "data_id"), f"[{table}] data_id: there is no crc")
            if isinstance(data_id, bool) or not isinstance(data_id, int) or not 0 <= data_id <= 0xFFFF:
                raise MapError(lines.of(table, "data_id"), f"[{table}] data_id: a whole number, 0..65535")
            use.data_id = data_id
        if "cycle_ms" in entry:
            cycle = entry["cycle_ms"]
            if isinstance(cycle, bool) or not isinstance(cycle, int) or not 1 <= cycle <= 60000:
                raise MapError(lines.of(table, "cycle_ms"), f"[{table}] cycle_ms: a whole number of ms, 1..60000")
            use.cycle_ms = cycle
    for name, use in uses.items():
        if not use.cycle_ms:
            raise MapError(lines.of(f"inputs.{use.inputs[0].column}", "message"),
                           f"{name} has no cycle time in the DBC (GenMsgCycleTime): give cycle_ms in [messages.{name}]")
    ordered = [uses[m.name] for m in dbc.messages if m.name in uses]
    return dbc_path, dbc, ordered, output_ids(document, lines, ordered)


def output_ids(document, lines, uses):
    """[outputs]: the CAN id of each of the estimator's frames, in bus_vocabulary.OUTPUTS' order,
    as (id, extended); lptn.dbc's where the map gives none. An id above 0x7FF is extended."""
    own = dbc_codegen.Parser(dbc_codegen.tokenize(dbc_codegen.read_text(LPTN_DBC))).parse()
    dbc_codegen.Checker(own).run()
    by_name = {m.name: m for m in own.messages}
    ids = {name: (by_name[name].can_id, by_name[name].extended) for name in bus_vocabulary.OUTPUTS}
    outputs = document.get("outputs", {})
    if not isinstance(outputs, dict):
        raise MapError(lines.of("", "outputs"), "outputs must be a table [outputs]")
    for name, value in outputs.items():
        if name not in ids:
            raise MapError(lines.of("outputs", name),
                           f"[outputs]: unknown key '{name}' ({', '.join(bus_vocabulary.OUTPUTS)})")
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 0x1FFFFFFF:
            raise MapError(lines.of("outputs", name),
                           f"[outputs] {name}: a CAN id, 0..0x1FFFFFFF (above 0x7FF an extended one)")
        ids[name] = (value, value > 0x7FF)
    taken = {(u.message.can_id, u.message.extended): u.message.name for u in uses}
    for name in bus_vocabulary.OUTPUTS:
        line = lines.of("outputs", name) if name in outputs else lines.of("outputs")
        can_id, extended = ids[name]
        if (can_id, extended) in taken:
            raise MapError(line, f"[outputs] {name}: id 0x{can_id:X} is {taken[(can_id, extended)]}'s too; "
                                 f"give {name} another id in [outputs]")
        taken[(can_id, extended)] = name
    return [ids[name] for name in bus_vocabulary.OUTPUTS]


def render(bus_name, dbc_path, dbc, uses, outputs, codecs, codec_namespace, namespace):
    dbc_codegen.check_cxx_names([m for m in dbc.messages if m.generated])
    lines = [
        f"// Generated by {GENERATOR} from {bus_name} ({os.path.basename(dbc_path)}); do not edit.",
        "// The converter's frames as the estimator's inputs: fw::BusDecoder for this bus.",
        "#pragma once",
        "#include <cstdint>",
        "",
        f'#include "{codecs}"',
        '#include "lptn/firmware/bus_decoder.hpp"',
        '#include "lptn/firmware/e2e.hpp"',
        "",
        f"namespace {namespace} {{",
        "",
    ]
    # The codecs are `dbc::` here; an alias only where they live elsewhere (an alias of a namespace
    # to itself is an error to clang, though g++ takes it).
    if codec_namespace != f"{namespace}::dbc":
        lines.append(f"namespace dbc = ::{codec_namespace};")
    lines += [
        f"inline constexpr int kMessages = {len(uses)};",
        f"static_assert(kMessages <= fw::kMaxBusMessages);",
        "",
        "// false: a frame of no message of the map. Otherwise `out` says what the frame carried.",
        "inline bool decode_frame(const void*, const fw::CanFrame& f, fw::BusReading& out) noexcept {",
        "  using fw::Input;",
        "  using fw::bit;",
    ]
    for index, use in enumerate(uses):
        m = use.message
        s = f"dbc::{m.cxx_name}"
        carried = " | ".join(f"bit(Input::{i.enumerator})" for i in use.inputs)
        fd = "!f.fd" if m.dlc > 8 else "f.fd"
        lines += [
            f"  if (f.id == {s}::kId && f.extended == {s}::kExtended) {{  // {m.name}",
            f"    out.message = {index};",
            f"    out.carried = static_cast<fw::InputMask>({carried});",
            f"    {s} m;",
            f"    if (f.remote || {fd} || f.len != {s}::kLength || !m.unpack(f.data, f.len)) {{",
            "      out.malformed = true;",
            "      return true;",
            "    }",
        ]
        if use.counter is not None:
            lines += [
                "    out.has_counter = true;",
                f"    out.counter = static_cast<std::uint8_t>(m.{dbc_codegen.member_name(use.counter)});",
                f"    out.counter_modulo = {1 << use.counter.length};",
                f"    out.max_delta_counter = {use.max_delta};",
            ]
        if use.crc is not None:
            lines += [
                "    out.has_crc = true;",
                f"    out.crc_ok = fw::e2e::frame_crc({use.data_id:#06x}, f.data, f.len, {use.crc_byte}) == "
                f"m.{dbc_codegen.member_name(use.crc)};",
            ]
        for i in use.inputs:
            member = dbc_codegen.member_name(i.signal)
            value = f"{s}::{dbc_codegen.base_name(i.signal)}_decode(m.{member})"
            if i.scale != 1.0 or i.offset != 0.0:
                value = f"{value} * {i.scale!r} + {i.offset!r}"
            add = f"out.add(Input::{i.enumerator}, static_cast<double>({value}));"
            if i.signal.multiplexed:
                lines.append(f"    if (m.{dbc_codegen.base_name(i.signal)}_is_present()) {add}")
            else:
                lines.append(f"    {add}")
        lines += ["    return true;", "  }"]
    cycles = {}
    for use in uses:
        for i in use.inputs:
            cycles[i.enumerator] = use.cycle_ms
    lines += [
        "  return false;",
        "}",
        "",
        "// The map's messages as SocketCAN ids for receive filters: extended ones with bit 31 (CAN_EFF_FLAG).",
        "inline constexpr std::uint32_t kFilterIds[] = {",
        *[f"    dbc::{u.message.cxx_name}::kId | (dbc::{u.message.cxx_name}::kExtended ? 0x80000000u : 0u),  // {u.message.name}"
          for u in uses],
        "};",
        "",
        "// The estimator's frames (lptn.dbc's LPTN_* messages) on this bus, in fw::pack_outputs' order.",
        "inline constexpr const char* kOutputNames[] = {"
        + ", ".join(f'"{name}"' for name in bus_vocabulary.OUTPUTS) + "};",
        "inline constexpr fw::OutputId kOutputIds[] = {",
        *[f"    {{{can_id:#x}u, {str(extended).lower()}}},  // {name}"
          for name, (can_id, extended) in zip(bus_vocabulary.OUTPUTS, outputs)],
        "};",
        "",
        "// The decoder, with each input's message cycle time (the inputs' timeouts follow from it).",
        "inline constexpr fw::BusDecoder decoder() noexcept {",
        "  fw::BusDecoder d{&decode_frame, nullptr, {}};",
    ]
    lines += [f"  d.input_cycle_ms[fw::index_of(fw::Input::{e})] = {c};" for e, c in cycles.items()]
    lines += [
        "  return d;",
        "}",
        "",
        f"}}  // namespace {namespace}",
        "",
    ]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description="Generate the firmware's glue to a converter's bus from bus.toml.")
    parser.add_argument("--bus", help="the bus map (bus.toml)")
    parser.add_argument("--codecs", help="the include path of the converter DBC's generated codecs")
    parser.add_argument("--codec-namespace", help="their namespace")
    parser.add_argument("--namespace", default="lptn::bus", help="namespace of the glue")
    parser.add_argument("--out", help="the header to write")
    parser.add_argument("--print-dbc", action="store_true", help="print the map's DBC file and exit")
    parser.add_argument("--vocabulary", action="store_true", help="write the map's vocabulary as C++ to --out")
    args = parser.parse_args(argv)
    if args.vocabulary:
        dbc_codegen.write_atomically(args.out, bus_vocabulary.render_header())
        return 0
    if not args.bus:
        parser.error("--bus is required")
    try:
        dbc_path, dbc, uses, outputs = read_map(args.bus)
    except OSError as error:
        print(f"{args.bus}:0: cannot read the file ({error.strerror})", file=sys.stderr)
        return 1
    except MapError as error:
        print(f"{args.bus}:{error.line}: {error.reason}", file=sys.stderr)
        return 1
    if args.print_dbc:
        print(dbc_path)
        return 0
    if not (args.out and args.codecs and args.codec_namespace):
        parser.error("--out, --codecs and --codec-namespace are required")
    header = render(os.path.basename(args.bus), dbc_path, dbc, uses, outputs, args.codecs, args.codec_namespace, args.namespace)
    dbc_codegen.write_atomically(args.out, header)
    return 0


if __name__ == "__main__":
    sys.exit(main())
