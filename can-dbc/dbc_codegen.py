#!/usr/bin/env python3
"""Generates the C++ CAN codecs (one header) from a DBC file.

    dbc_codegen.py --dbc lptn.dbc --node LPTN --namespace lptn::can --out DIR/lptn/can/lptn_frames.hpp

The DBC is the single source of truth for every CAN frame, so the build runs this script whenever
the DBC changes. A DBC that is malformed, or that the generated code could not honour, stops the
build: one line `FILE:LINE: reason` on stderr, exit status 1, and no output file.

Python 3.11 standard library only: the build host may have nothing else.
"""

import argparse
import math
import os
import re
import sys
import tempfile
import textwrap
from dataclasses import dataclass, field
from fractions import Fraction

GENERATOR = "can-dbc/dbc_codegen.py"
NO_NODE = "Vector__XXX"  # what DBC tools write where a sender or receiver is "none"
# Vector tools park signals that belong to no frame in this pseudo message; it is not a frame.
INDEPENDENT_SIGNALS_ID = 0xC0000000
EXTENDED_FLAG = 0x80000000


class DbcError(Exception):
    def __init__(self, line, reason):
        super().__init__(reason)
        self.line = line
        self.reason = reason


# ---------------------------------------------------------------------------------------------
# Tokens

@dataclass(frozen=True)
class Token:
    kind: str  # ident, number, string, punct, eof
    text: str
    line: int


_TOKEN = re.compile(r"""
    (?P<space>[ \t\r\f\v]+)
  | (?P<newline>\n)
  | (?P<string>"(?:\\.|[^"\\])*")
  | (?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)
  | (?P<ident>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<punct>[:;|@(),\[\]+-])
""", re.VERBOSE | re.DOTALL)


def tokenize(text):
    """Signs are separate tokens (the parser joins them to numbers): `@1-` is `@`, `1`, `-`."""
    tokens, line, pos = [], 1, 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if match is None:
            if text[pos] == '"':
                raise DbcError(line, "unterminated string")
            raise DbcError(line, f"unexpected character {text[pos]!r}")
        if match.lastgroup not in ("space", "newline"):
            tokens.append(Token(match.lastgroup, match.group(), line))
        line += match.group().count("\n")
        pos = match.end()
    tokens.append(Token("eof", "", line))
    return tokens


def _describe(token):
    return {"eof": "end of file", "string": "a string"}.get(token.kind, f"'{token.text}'")


# ---------------------------------------------------------------------------------------------
# Model

@dataclass(frozen=True)
class Number:
    """A DBC number: its text for comments, its exact value for range arithmetic."""
    text: str
    value: Fraction

    @property
    def double(self):
        return float(self.value)


@dataclass
class Signal:
    name: str
    line: int
    start: int
    length: int
    big_endian: bool
    signed: bool
    factor: Number
    offset: Number
    minimum: Number
    maximum: Number
    unit: str
    receivers: list
    comment: str = None
    values: list = None  # [(raw, description)] from VAL_


@dataclass
class Message:
    dbc_id: int  # as written, with the extended flag
    name: str
    line: int
    dlc: int
    sender: str
    signals: list = field(default_factory=list)
    comment: str = None
    cycle_time: int = None
    transmitters: list = field(default_factory=list)  # from BO_TX_BU_

    @property
    def extended(self):
        return bool(self.dbc_id & EXTENDED_FLAG)

    @property
    def is_frame(self):
        return self.dbc_id != INDEPENDENT_SIGNALS_ID

    @property
    def can_id(self):
        return self.dbc_id & ~EXTENDED_FLAG


@dataclass
class AttributeDef:
    line: int
    object_kind: str  # "" (network), BU_, BO_, SG_ or EV_
    type: str  # INT, HEX, FLOAT, STRING or ENUM
    minimum: Fraction = None
    maximum: Fraction = None
    choices: list = None


# Statements that name other objects; resolved once the whole file is read, in file order.
@dataclass
class CommentStmt:
    line: int
    kind: str
    key: object
    text: str


@dataclass
class AttrDefaultStmt:
    line: int
    name: str
    value: object  # Fraction or str


@dataclass
class AttrValueStmt:
    line: int
    name: str
    kind: str
    key: object
    value: object


@dataclass
class ValuesStmt:
    line: int
    message_id: int
    signal: str
    pairs: list


@dataclass
class ValueTypeStmt:
    line: int
    message_id: int
    signal: str
    value_type: int


@dataclass
class TransmittersStmt:
    line: int
    message_id: int
    nodes: list


@dataclass
class Dbc:
    nodes: list = field(default_factory=list)  # [(name, line)]
    nodes_line: int = None
    comment: str = None
    node_comments: dict = field(default_factory=dict)
    messages: list = field(default_factory=list)
    attribute_defs: dict = field(default_factory=dict)
    statements: list = field(default_factory=list)


# ---------------------------------------------------------------------------------------------
# Parser

OBJECT_KINDS = ("BU_", "BO_", "SG_", "EV_")
# Sections real tools write that the codecs do not need: read up to their ';' and dropped.
SKIPPED_SECTIONS = {
    "BA_DEF_REL_", "BA_REL_", "BA_DEF_DEF_REL_", "BA_DEF_SGTYPE_", "BA_SGTYPE_", "SIG_GROUP_",
    "SIGTYPE_VALTYPE_", "SIG_TYPE_REF_", "EV_", "EV_DATA_", "ENVVAR_DATA_", "SGTYPE_",
    "SGTYPE_VAL_", "CAT_DEF_", "CAT_", "FILTER", "BU_SG_REL_", "BU_EV_REL_", "BU_BO_REL_",
    "NS_DESC_",
}


class Parser:
    def __init__(self, tokens):
        self.tokens = tokens
        self.pos = 0
        self.dbc = Dbc()
        self.message = None  # the BO_ that SG_ lines belong to
        self.value_tables = set()

    # -- token helpers
    def peek(self):
        return self.tokens[self.pos]

    def take(self):
        token = self.tokens[self.pos]
        if token.kind != "eof":
            self.pos += 1
        return token

    def fail(self, token, expected):
        raise DbcError(token.line, f"expected {expected}, found {_describe(token)}")

    def at_punct(self, char):
        token = self.peek()
        return token.kind == "punct" and token.text == char

    def accept_punct(self, char):
        if self.at_punct(char):
            self.take()
            return True
        return False

    def punct(self, char, context):
        """Missing punctuation is reported where the statement stopped, as compilers do for a
        missing ';', not on the line of whatever follows."""
        if not self.accept_punct(char):
            found = self.peek()
            line = self.tokens[self.pos - 1].line if self.pos else found.line
            raise DbcError(line, f"expected '{char}' {context}, found {_describe(found)}")

    def ident(self, what):
        token = self.take()
        if token.kind != "ident":
            self.fail(token, what)
        return token.text

    def string(self, what):
        token = self.take()
        if token.kind != "string":
            self.fail(token, what)
        return re.sub(r'\\(["\\])', r"\1", token.text[1:-1])

    def number(self, what):
        sign = self.take().text if self.at_punct("-") or self.at_punct("+") else ""
        token = self.take()
        if token.kind != "number":
            self.fail(token, what)
        text = sign + token.text
        exponent = re.search(r"[eE]([+-]?[0-9]+)$", text)
        # Checked before Fraction, which would spell out 1e99999999 digit by digit.
        if exponent and abs(int(exponent.group(1))) > 300 or len(text) > 300:
            raise DbcError(token.line, f"number {text[:20]} is out of range")
        value = Fraction(text)
        if abs(value) > Fraction(10) ** 300:
            raise DbcError(token.line, f"number {text} is out of range")
        return Number(text, value)

    def integer(self, what):
        start = self.peek()
        number = self.number(what)
        if number.value.denominator != 1 or not number.text.lstrip("+-").isdigit():
            self.fail(start, what)
        return int(number.value)

    def natural(self, what):
        """A count or a position: an integer written without a sign."""
        if self.at_punct("-") or self.at_punct("+"):
            self.fail(self.peek(), what)
        return self.integer(what)

    def value(self, what):
        """An attribute value: a number or a string."""
        if self.peek().kind == "string":
            return self.string(what)
        return self.number(what).value

    def end(self, section):
        self.punct(";", f"at the end of {section}")

    # -- sections
    def parse(self):
        while (token := self.take()).kind != "eof":
            if token.kind != "ident":
                self.fail(token, "a section keyword such as BO_ or CM_")
            if token.text != "SG_":
                self.message = None
            handler = self.SECTIONS.get(token.text)
            if handler:
                handler(self, token)
            elif token.text in SKIPPED_SECTIONS:
                self.skip(token)
            else:
                raise DbcError(token.line, f"unknown section '{token.text}'")
        return self.dbc

    def skip(self, keyword):
        while not self.accept_punct(";"):
            if self.take().kind == "eof":
                raise DbcError(keyword.line, f"{keyword.text} has no ';' at its end")

    def version(self, _):
        self.string("a version string after VERSION")

    def new_symbols(self, _):
        # The list of keywords the file may use; it ends where the mandatory BS_ (or BU_) starts.
        self.punct(":", "after NS_")
        while self.peek().kind == "ident" and self.peek().text not in ("BS_", "BU_"):
            self.take()

    def bit_timing(self, _):
        self.punct(":", "after BS_")
        if self.peek().kind == "number":
            self.integer("a baud rate")
            self.punct(":", "after the baud rate")
            self.integer("BTR1")
            self.punct(",", "between BTR1 and BTR2")
            self.integer("BTR2")

    def nodes(self, keyword):
        if self.dbc.nodes_line is not None:
            raise DbcError(keyword.line, f"second BU_ section (the first is on line {self.dbc.nodes_line})")
        self.dbc.nodes_line = keyword.line
        self.punct(":", "after BU_")
        while self.peek().kind == "ident" and self.peek().text not in self.SECTIONS \
                and self.peek().text not in SKIPPED_SECTIONS:
            token = self.take()
            self.dbc.nodes.append((token.text, token.line))

    def message_def(self, keyword):
        dbc_id = self.natural("a message id after BO_")
        name = self.ident("a message name")
        self.punct(":", "after the message name")
        dlc = self.natural("the message length (DLC)")
        sender = self.ident("the sending node")
        self.message = Message(dbc_id, name, keyword.line, dlc, sender)
        self.dbc.messages.append(self.message)

    def signal_def(self, keyword):
        if self.message is None:
            raise DbcError(keyword.line, "SG_ must follow its message's BO_ line")
        name = self.ident("a signal name after SG_")
        if self.peek().kind == "ident":
            raise DbcError(keyword.line, f"signal {name}: multiplexed signals are not supported")
        self.punct(":", "after the signal name")
        start = self.natural("the start bit")
        self.punct("|", "between start bit and length")
        length = self.natural("the signal length")
        self.punct("@", "before the byte order")
        order_token = self.peek()
        order = self.natural("the byte order (0 or 1)")
        if order not in (0, 1):
            self.fail(order_token, "the byte order 0 (Motorola) or 1 (Intel)")
        sign = self.take()
        if sign.kind != "punct" or sign.text not in "+-":
            self.fail(sign, "'+' (unsigned) or '-' (signed) after the byte order")
        self.punct("(", "before the factor")
        factor = self.number("the factor")
        self.punct(",", "between factor and offset")
        offset = self.number("the offset")
        self.punct(")", "after the offset")
        self.punct("[", "before the minimum")
        minimum = self.number("the minimum")
        self.punct("|", "between minimum and maximum")
        maximum = self.number("the maximum")
        self.punct("]", "after the maximum")
        unit = self.string("the unit string")
        receivers = [self.ident("a receiving node")]
        while self.accept_punct(","):
            receivers.append(self.ident("a receiving node after ','"))
        self.message.signals.append(Signal(
            name, keyword.line, start, length, order == 0, sign.text == "-", factor, offset,
            minimum, maximum, unit, receivers))

    def object_ref(self, kinds):
        """`BU_ node`, `BO_ id`, `SG_ id signal` or `EV_ name` (or nothing: the network)."""
        token = self.peek()
        if token.kind != "ident" or token.text not in kinds:
            return "", None
        kind = self.take().text
        if kind == "BO_":
            return kind, self.integer("a message id")
        if kind == "SG_":
            message_id = self.integer("a message id")
            return kind, (message_id, self.ident("a signal name"))
        return kind, self.ident("a node name" if kind == "BU_" else "an environment variable")

    def comment(self, keyword):
        kind, key = self.object_ref(OBJECT_KINDS)
        text = self.string("the comment string")
        self.end("CM_")
        self.dbc.statements.append(CommentStmt(keyword.line, kind, key, text))

    def attribute_def(self, keyword):
        kind = self.take().text if self.peek().text in OBJECT_KINDS else ""
        name = self.string("the attribute name")
        if name in self.dbc.attribute_defs:
            first = self.dbc.attribute_defs[name].line
            raise DbcError(keyword.line, f'attribute "{name}" is already defined on line {first}')
        type_token = self.peek()
        definition = AttributeDef(keyword.line, kind, self.ident("an attribute type"))
        if definition.type in ("INT", "HEX"):
            definition.minimum = Fraction(self.integer("the minimum"))
            definition.maximum = Fraction(self.integer("the maximum"))
        elif definition.type == "FLOAT":
            definition.minimum = self.number("the minimum").value
            definition.maximum = self.number("the maximum").value
        elif definition.type == "ENUM":
            definition.choices = [self.string("an enum value")]
            while self.accept_punct(","):
                definition.choices.append(self.string("an enum value after ','"))
        elif definition.type != "STRING":
            self.fail(type_token, "an attribute type (INT, HEX, FLOAT, STRING or ENUM)")
        self.end("BA_DEF_")
        self.dbc.attribute_defs[name] = definition

    def attribute_default(self, keyword):
        name = self.string("the attribute name")
        value = self.value("the default value")
        self.end("BA_DEF_DEF_")
        self.dbc.statements.append(AttrDefaultStmt(keyword.line, name, value))

    def attribute_value(self, keyword):
        name = self.string("the attribute name")
        kind, key = self.object_ref(OBJECT_KINDS)
        value = self.value("the attribute value")
        self.end("BA_")
        self.dbc.statements.append(AttrValueStmt(keyword.line, name, kind, key, value))

    def value_pairs(self, section):
        pairs, seen = [], set()
        while not self.accept_punct(";"):
            token = self.peek()
            raw = self.integer(f"a raw value or the ';' that ends {section}")
            if raw in seen:
                raise DbcError(token.line, f"value {raw} is described twice")
            seen.add(raw)
            pairs.append((raw, self.string("the value's description")))
        return pairs

    def value_descriptions(self, keyword):
        if self.peek().kind == "ident":  # VAL_ of an environment variable: not a frame's business
            self.take()
            self.value_pairs("VAL_")
            return
        message_id = self.integer("a message id or environment variable after VAL_")
        signal = self.ident("a signal name")
        pairs = self.value_pairs("VAL_")
        self.dbc.statements.append(ValuesStmt(keyword.line, message_id, signal, pairs))

    def value_table(self, keyword):
        name = self.ident("a value table name")
        if name in self.value_tables:
            raise DbcError(keyword.line, f"value table {name} is defined twice")
        self.value_tables.add(name)
        self.value_pairs("VAL_TABLE_")

    def value_type(self, keyword):
        message_id = self.integer("a message id after SIG_VALTYPE_")
        signal = self.ident("a signal name")
        self.accept_punct(":")
        value_type = self.integer("the value type (0 integer, 1 float, 2 double)")
        self.end("SIG_VALTYPE_")
        self.dbc.statements.append(ValueTypeStmt(keyword.line, message_id, signal, value_type))

    def transmitters(self, keyword):
        message_id = self.integer("a message id after BO_TX_BU_")
        self.punct(":", "after the message id")
        nodes = [self.ident("a node name")]
        while self.accept_punct(","):
            nodes.append(self.ident("a node name after ','"))
        self.end("BO_TX_BU_")
        self.dbc.statements.append(TransmittersStmt(keyword.line, message_id, nodes))

    def multiplexing(self, keyword):
        raise DbcError(keyword.line, "multiplexed signals are not supported (SG_MUL_VAL_)")

    SECTIONS = {
        "VERSION": version, "NS_": new_symbols, "BS_": bit_timing, "BU_": nodes,
        "BO_": message_def, "SG_": signal_def, "CM_": comment, "BA_DEF_": attribute_def,
        "BA_DEF_DEF_": attribute_default, "BA_": attribute_value, "VAL_": value_descriptions,
        "VAL_TABLE_": value_table, "SIG_VALTYPE_": value_type, "BO_TX_BU_": transmitters,
        "SG_MUL_VAL_": multiplexing,
    }


# ---------------------------------------------------------------------------------------------
# Signal layout

def raw_limits(signal):
    """The raw values `length` bits hold."""
    if signal.signed:
        return -(1 << (signal.length - 1)), (1 << (signal.length - 1)) - 1
    return 0, (1 << signal.length) - 1


def frame_bits(signal):
    """Frame bit (8 * byte + bit in byte) of each value bit, least significant bit first."""
    if not signal.big_endian:
        return [signal.start + i for i in range(signal.length)]
    # Motorola: the start bit is the MSB; DBC numbers bits in a sawtooth, so after bit 0 of a byte
    # the signal continues at bit 7 of the next byte.
    walk, position = [], signal.start
    for _ in range(signal.length):
        walk.append(position)
        position = position + 15 if position % 8 == 0 else position - 1
    return walk[::-1]


@dataclass(frozen=True)
class Chunk:
    """Bits [low, low + width) of frame byte `byte` hold value bits [shift, shift + width)."""
    byte: int
    low: int
    width: int
    shift: int


def chunks(signal):
    result = []
    for value_bit, bit in enumerate(frame_bits(signal)):
        byte, low = divmod(bit, 8)
        if result and result[-1].byte == byte and result[-1].low + result[-1].width == low:
            last = result[-1]
            result[-1] = Chunk(byte, last.low, last.width + 1, last.shift)
        else:
            result.append(Chunk(byte, low, 1, value_bit))
    return sorted(result, key=lambda chunk: chunk.byte)


def in_range_raw_bounds(signal):
    """Exact raw bounds of the DBC's physical [min|max], or None for [0|0] (no range)."""
    if signal.minimum.value == 0 and signal.maximum.value == 0:
        return None
    factor, offset = signal.factor.value, signal.offset.value
    ends = sorted(((signal.minimum.value - offset) / factor, (signal.maximum.value - offset) / factor))
    return ends[0], ends[1]


# ---------------------------------------------------------------------------------------------
# Validation

class Checker:
    def __init__(self, dbc):
        self.dbc = dbc
        self.nodes = {}
        self.by_id = {}
        self.seen_statements = {}

    def run(self):
        self.check_nodes()
        self.check_messages()
        for statement in self.dbc.statements:
            self.RESOLVERS[type(statement)](self, statement)
        self.apply_default_cycle_time()

    def check_nodes(self):
        for name, line in self.dbc.nodes:
            if name in self.nodes:
                raise DbcError(line, f"node {name} is listed twice in BU_")
            self.nodes[name] = line

    def check_node(self, name, line, role):
        if name != NO_NODE and name not in self.nodes:
            raise DbcError(line, f"{role} '{name}' is not a node in BU_")

    def check_messages(self):
        by_name = {}
        for message in self.dbc.messages:
            if message.dbc_id in self.by_id:
                first = self.by_id[message.dbc_id]
                raise DbcError(message.line, f"message id {message.dbc_id} (0x{message.can_id:X}) is already "
                                             f"used by {first.name} on line {first.line}")
            self.by_id[message.dbc_id] = message
            if not message.is_frame:
                continue
            if message.name in by_name:
                raise DbcError(message.line, f"message name {message.name} is already used on line "
                                             f"{by_name[message.name].line}")
            by_name[message.name] = message
            self.check_message(message)

    def check_message(self, message):
        limit = 0x1FFFFFFF if message.extended else 0x7FF
        if message.can_id > limit:
            kind = "extended id does not fit in 29" if message.extended else "standard id does not fit in 11"
            raise DbcError(message.line, f"message {message.name}: {kind} bits (0x{message.can_id:X})")
        if message.dlc > 8:
            raise DbcError(message.line, f"message {message.name}: DLC {message.dlc} is more than 8 bytes; "
                                         "only classic CAN is supported (no CAN FD)")
        self.check_node(message.sender, message.line, f"message {message.name}: sender")
        if not message.signals:
            raise DbcError(message.line, f"message {message.name} has no signals")
        owners = {}
        names = {}
        for signal in message.signals:
            if signal.name in names:
                raise DbcError(signal.line, f"signal {signal.name} appears twice in message {message.name} "
                                            f"(first on line {names[signal.name]})")
            names[signal.name] = signal.line
            self.check_signal(message, signal)
            for bit in frame_bits(signal):
                if bit in owners:
                    raise DbcError(signal.line, f"signal {signal.name} overlaps signal {owners[bit]} "
                                                f"in message {message.name} (frame bit {bit})")
                owners[bit] = signal.name

    def check_signal(self, message, signal):
        where = f"signal {signal.name}"
        if not 1 <= signal.length <= 64:
            raise DbcError(signal.line, f"{where}: length {signal.length} is not in 1..64")
        if signal.factor.value == 0:
            raise DbcError(signal.line, f"{where}: factor 0 (every raw value would decode to the offset)")
        if signal.minimum.value > signal.maximum.value:
            raise DbcError(signal.line, f"{where}: minimum {signal.minimum.text} is greater than "
                                        f"maximum {signal.maximum.text}")
        if max(frame_bits(signal)) >= 8 * message.dlc:
            order = "big-endian" if signal.big_endian else "little-endian"
            raise DbcError(signal.line, f"{where} ({order}, start bit {signal.start}, {signal.length} bits) "
                                        f"overflows its {message.dlc}-byte frame")
        for receiver in signal.receivers:
            self.check_node(receiver, signal.line, f"signal {signal.name}: receiver")
        self.check_range(signal)

    @staticmethod
    def check_range(signal):
        bounds = in_range_raw_bounds(signal)
        if bounds is None:
            return
        low, high = raw_limits(signal)
        where = f"signal {signal.name}: range [{signal.minimum.text}|{signal.maximum.text}]"
        if bounds[0] < low or bounds[1] > high:
            kind = "signed" if signal.signed else "unsigned"
            raise DbcError(signal.line, f"{where} needs raw values {_fmt(bounds[0])}..{_fmt(bounds[1])} "
                                        f"but {signal.length} {kind} bits cannot represent them "
                                        f"(they hold {low}..{high})")
        if math.ceil(bounds[0]) > math.floor(bounds[1]):
            raise DbcError(signal.line, f"{where} contains no raw value")

    # -- statements that refer to other objects
    def message(self, message_id, line):
        if message_id not in self.by_id:
            raise DbcError(line, f"no message has id {message_id}")
        return self.by_id[message_id]

    def signal(self, message_id, name, line):
        message = self.message(message_id, line)
        for signal in message.signals:
            if signal.name == name:
                return message, signal
        raise DbcError(line, f"message {message.name} has no signal {name}")

    def once(self, what, key, line):
        if key in self.seen_statements:
            raise DbcError(line, f"second {what} (the first is on line {self.seen_statements[key]})")
        self.seen_statements[key] = line

    def resolve_comment(self, stmt):
        target = {"BU_": f"node {stmt.key}", "BO_": f"message {stmt.key}", "SG_": f"signal {stmt.key}",
                  "EV_": f"environment variable {stmt.key}", "": "the network"}[stmt.kind]
        self.once(f"comment for {target}", ("CM_", stmt.kind, stmt.key), stmt.line)
        if stmt.kind == "":
            self.dbc.comment = stmt.text
        elif stmt.kind == "BU_":
            self.check_node(stmt.key, stmt.line, "CM_ BU_:")
            self.dbc.node_comments[stmt.key] = stmt.text
        elif stmt.kind == "BO_":
            self.message(stmt.key, stmt.line).comment = stmt.text
        elif stmt.kind == "SG_":
            self.signal(*stmt.key, stmt.line)[1].comment = stmt.text

    def definition(self, name, line):
        if name not in self.dbc.attribute_defs:
            raise DbcError(line, f'attribute "{name}" has no BA_DEF_')
        return self.dbc.attribute_defs[name]

    def resolve_attr_default(self, stmt):
        self.once(f'default for attribute "{stmt.name}"', ("BA_DEF_DEF_", stmt.name), stmt.line)
        check_attribute_value(stmt.name, self.definition(stmt.name, stmt.line), stmt.value, stmt.line)

    def resolve_attr_value(self, stmt):
        definition = self.definition(stmt.name, stmt.line)
        if definition.object_kind != stmt.kind:
            raise DbcError(stmt.line, f'attribute "{stmt.name}" is defined for '
                                      f'{definition.object_kind or "the network"}, not {stmt.kind or "the network"}')
        self.once(f'value of attribute "{stmt.name}" for {stmt.kind} {stmt.key}',
                  ("BA_", stmt.name, stmt.kind, stmt.key), stmt.line)
        check_attribute_value(stmt.name, definition, stmt.value, stmt.line)
        if stmt.kind == "BU_":
            self.check_node(stmt.key, stmt.line, "BA_ BU_:")
        elif stmt.kind == "BO_":
            message = self.message(stmt.key, stmt.line)
            if stmt.name == "GenMsgCycleTime":
                message.cycle_time = cycle_time(stmt.value, stmt.line)
        elif stmt.kind == "SG_":
            self.signal(*stmt.key, stmt.line)

    def resolve_values(self, stmt):
        self.once(f"VAL_ for signal {stmt.signal}", ("VAL_", stmt.message_id, stmt.signal), stmt.line)
        message, signal = self.signal(stmt.message_id, stmt.signal, stmt.line)
        if not message.is_frame:  # its signals are never checked, nor generated
            return
        low, high = raw_limits(signal)
        for raw, _ in stmt.pairs:
            if not low <= raw <= high:
                raise DbcError(stmt.line, f"VAL_ value {raw} does not fit signal {signal.name} "
                                          f"(raw {low}..{high})")
        signal.values = stmt.pairs

    def resolve_value_type(self, stmt):
        message, signal = self.signal(stmt.message_id, stmt.signal, stmt.line)
        if message.is_frame and stmt.value_type != 0:
            raise DbcError(stmt.line, f"signal {signal.name}: IEEE float signals (SIG_VALTYPE_ "
                                      f"{stmt.value_type}) are not supported")

    def resolve_transmitters(self, stmt):
        message = self.message(stmt.message_id, stmt.line)
        for node in stmt.nodes:
            self.check_node(node, stmt.line, f"message {message.name}: transmitter")
        message.transmitters.extend(stmt.nodes)

    def apply_default_cycle_time(self):
        default = 0
        for stmt in self.dbc.statements:
            if isinstance(stmt, AttrDefaultStmt) and stmt.name == "GenMsgCycleTime":
                default = cycle_time(stmt.value, stmt.line)
        for message in self.dbc.messages:
            if message.cycle_time is None:
                message.cycle_time = default

    RESOLVERS = {
        CommentStmt: resolve_comment, AttrDefaultStmt: resolve_attr_default,
        AttrValueStmt: resolve_attr_value, ValuesStmt: resolve_values,
        ValueTypeStmt: resolve_value_type, TransmittersStmt: resolve_transmitters,
    }


def _fmt(value):
    return str(int(value)) if value.denominator == 1 else f"{float(value):g}"


def check_attribute_value(name, definition, value, line):
    if definition.type in ("INT", "HEX", "FLOAT"):
        if not isinstance(value, Fraction):
            raise DbcError(line, f'attribute "{name}" takes a number')
        if definition.type != "FLOAT" and value.denominator != 1:
            raise DbcError(line, f'attribute "{name}" takes an integer')
        # [0|0] and the like mean "no limits" in files real tools write.
        bounded = definition.minimum != definition.maximum
        if bounded and not definition.minimum <= value <= definition.maximum:
            raise DbcError(line, f'value {_fmt(value)} of attribute "{name}" is outside its range '
                                 f'[{_fmt(definition.minimum)}, {_fmt(definition.maximum)}]')
    elif definition.type == "STRING":
        if not isinstance(value, str):
            raise DbcError(line, f'attribute "{name}" takes a string')
    elif isinstance(value, str):
        if value not in definition.choices:
            raise DbcError(line, f'"{value}" is not one of the values of attribute "{name}"')
    elif value.denominator != 1 or not 0 <= value < len(definition.choices):
        raise DbcError(line, f'value {_fmt(value)} is not an index into the values of attribute "{name}"')


def cycle_time(value, line):
    if not isinstance(value, Fraction) or value.denominator != 1 or not 0 <= value < 2 ** 32:
        raise DbcError(line, "GenMsgCycleTime must be a whole number of milliseconds (0..4294967295)")
    return int(value)


# ---------------------------------------------------------------------------------------------
# C++ names

CXX_KEYWORDS = set("""
alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t
char32_t class compl concept const consteval constexpr constinit const_cast continue co_await
co_return co_yield decltype default delete do double dynamic_cast else enum explicit export extern
false float for friend goto if inline int long mutable namespace new noexcept not not_eq nullptr
operator or or_eq private protected public register reinterpret_cast requires return short signed
sizeof static static_assert static_cast struct switch template this thread_local throw true try
typedef typeid typename union unsigned using virtual void volatile wchar_t while xor xor_eq
""".split())
# pack() and unpack() use these as parameters and locals; a member of the same name would be
# shadowed (-Wshadow).
PACK_LOCALS = {"dst", "src", "size", "bits", "i"}
STRUCT_CONSTANTS = ("kId", "kExtended", "kLength", "kCycleTimeMs", "kName", "kSender", "kSignals",
                    "kNumSignals", "pack", "unpack", "SignalInfo")
NAMESPACE_NAMES = ("SignalInfo", "detail", "kReceivedIds", "kTransmittedIds")


def camel_case(name):
    """TC_Electrical -> TcElectrical: all-capital words become Capitalised."""
    parts = [part for part in name.split("_") if part]
    return "".join(part.capitalize() if part.isupper() else part[0].upper() + part[1:] for part in parts)


def snake_case(name):
    """MotorSpeed -> motor_speed, ABSActive -> abs_active."""
    text = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1_\2", name)
    text = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", text)
    return re.sub(r"_+", "_", text).strip("_").lower()


def member_name(signal):
    base = snake_case(signal.name)
    return base + "_" if base in CXX_KEYWORDS or base in PACK_LOCALS else base


def enumerator_names(pairs):
    """Descriptions as C++ enumerators; repeated ones ("reserved") get their value appended."""
    def value_suffix(raw):
        return str(raw) if raw >= 0 else f"minus_{-raw}"

    bases = []
    for raw, description in pairs:
        base = re.sub(r"[^A-Za-z0-9]+", "_", description).strip("_")
        if not base:
            base = "value_" + value_suffix(raw)
        elif base[0].isdigit():
            base = "value_" + base
        bases.append(base + "_" if base in CXX_KEYWORDS else base)
    return [base + "_" + value_suffix(raw) if bases.count(base) > 1 else base
            for base, (raw, _) in zip(bases, pairs)]


def _claim(names, name, owner, line):
    if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        raise DbcError(line, f"{owner} gives no valid C++ name ('{name}')")
    if name in names:
        raise DbcError(line, f"{owner}: its C++ name '{name}' clashes with {names[name]}")
    names[name] = owner


def check_cxx_names(messages):
    """Different DBC names can meet in C++ (TC_Speed and TcSpeed, Speed and speed_decode)."""
    global_names = {name: "a name the header defines" for name in NAMESPACE_NAMES}
    for message in messages:
        struct = camel_case(message.name)
        _claim(global_names, struct, f"message {message.name}", message.line)
        members = {name: "a name the header defines" for name in STRUCT_CONSTANTS}
        members[struct] = "the struct's own name"
        for signal in message.signals:
            owner = f"signal {signal.name}"
            base = snake_case(signal.name)
            for name in (member_name(signal), base + "_decode", base + "_encode", base + "_is_in_range"):
                _claim(members, name, owner, signal.line)
            if signal.values is not None:
                _claim(members, camel_case(signal.name), owner, signal.line)
                enumerators = {}
                for name in enumerator_names(signal.values):
                    _claim(enumerators, name, f"VAL_ of {signal.name}", signal.line)


# ---------------------------------------------------------------------------------------------
# C++ text

def cxx_type(signal):
    width = next(width for width in (8, 16, 32, 64) if signal.length <= width)
    return f"std::{'' if signal.signed else 'u'}int{width}_t", width


def unsigned_type(signal):
    return f"std::uint{cxx_type(signal)[1]}_t"


def int_literal(value, signed):
    if value == -(1 << 63):
        return "(-9223372036854775807 - 1)"  # the literal 9223372036854775808 does not exist
    return str(value) if signed else f"{value}u"


def hex_mask(width):
    return f"0x{(1 << width) - 1:0{max(2, (width + 3) // 4)}X}u"


def string_literal(text):
    out = []
    for byte in text.encode("utf-8"):
        if chr(byte) in '"\\':
            out.append("\\" + chr(byte))
        elif 0x20 <= byte < 0x7F:
            out.append(chr(byte))
        else:
            out.append(f"\\{byte:03o}")  # octal: a \x escape would swallow hex digits after it
    return '"' + "".join(out) + '"'


def _ascii(char):
    """Printable ASCII stays; the rest, and the backslash, become \\x.. escapes. A backslash at
    the end of a // line would splice the next line into the comment."""
    code = ord(char)
    if 0x20 <= code < 0x7F and char != "\\":
        return char
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def ascii_text(text):
    return "".join(_ascii(char) for char in " ".join(text.split()))


def comment_lines(text, indent, width=100):
    escaped = ascii_text(text)
    wrapped = textwrap.wrap(escaped, width - len(indent) - 3, break_long_words=False, break_on_hyphens=False)
    return [f"{indent}// {line}" for line in wrapped]


def sg_notation(signal):
    """The SG_ definition as the DBC writes it, for the reader who checks against the file."""
    return (f"{signal.start}|{signal.length}@{0 if signal.big_endian else 1}{'-' if signal.signed else '+'} "
            f"({signal.factor.text},{signal.offset.text}) [{signal.minimum.text}|{signal.maximum.text}] "
            f"{string_literal(signal.unit)}")


def pack_lines(signal):
    """dst[byte] |= the value bits that byte holds: one line per byte the signal touches."""
    lines = [f"    // {signal.name} {sg_notation(signal)}"]
    source, indent = member_name(signal), "    "
    if signal.signed:  # shift and mask the two's complement bits, not a negative number
        lines += ["    {", f"      const auto bits = static_cast<{unsigned_type(signal)}>({source});"]
        source, indent = "bits", "      "
    for chunk in chunks(signal):
        value = f"({source} >> {chunk.shift})" if chunk.shift else source
        term = f"({value} & {hex_mask(chunk.width)})"
        if chunk.low:
            term = f"({term} << {chunk.low})"
        lines.append(f"{indent}dst[{chunk.byte}] = static_cast<std::uint8_t>(dst[{chunk.byte}] | {term});")
    if signal.signed:
        lines.append("    }")
    return lines


def gather_terms(signal):
    """The value bits each byte of src[] holds, moved to their place in the raw value, as
    (expression, is it a single operand). Below 32 bits the terms are plain ints (a byte shifted
    by up to 23 bits fits); from 32 bits on each byte is widened to the raw value's unsigned type."""
    wide = cxx_type(signal)[1] >= 32
    # Narrow terms are int, or unsigned once masked: mask all or none, so that `|` never mixes
    # signedness (clang's -Wsign-conversion).
    mask_all = not wide and any(chunk.width < 8 for chunk in chunks(signal))
    terms = []
    for chunk in chunks(signal):
        term, single = f"src[{chunk.byte}]", True
        if chunk.low:
            term, single = f"{term} >> {chunk.low}", False
        if chunk.width < 8 or mask_all:
            term, single = f"{_operand(term, single)} & {hex_mask(chunk.width)}", False
        if wide:
            term, single = f"static_cast<{unsigned_type(signal)}>({term})", True
        if chunk.shift:
            term, single = f"{_operand(term, single)} << {chunk.shift}", False
        terms.append((term, single))
    return terms


def _operand(term, single):
    return term if single else f"({term})"


def gather_expression(signal, type_name, prefix):
    """The signal's bits from src[] as a type_name, to follow `prefix` on its line; one byte per
    line if the statement would not fit in 100 columns."""
    terms = gather_terms(signal)
    if len(terms) == 1:
        return f"static_cast<{type_name}>({terms[0][0]})"
    operands = [_operand(term, single) for term, single in terms]
    if cxx_type(signal)[1] >= 32 and type_name == unsigned_type(signal):
        opening, closing = "", ""  # the terms are of that type already
    else:
        opening, closing = f"static_cast<{type_name}>(", ")"
    one_line = f"{opening}{' | '.join(operands)}{closing}"
    if len(prefix) + len(one_line) + 1 <= 100:
        return one_line
    indent = prefix[:len(prefix) - len(prefix.lstrip())]
    first_break = f"\n{indent}    " if opening else ""
    return opening + first_break + f" |\n{indent}    ".join(operands) + closing


def unpack_lines(signal):
    stype, width = cxx_type(signal)
    target = member_name(signal)
    lines = [f"    // {signal.name} {sg_notation(signal)}"]
    if not signal.signed or signal.length == width:
        # A full-width signed value converts modulo 2^width: the bits are its two's complement.
        prefix = f"    {target} = "
        lines.append(f"{prefix}{gather_expression(signal, stype, prefix)};")
    else:
        sign_bit = f"0x{1 << (signal.length - 1):X}u"
        above = f"0x{((1 << width) - 1) ^ ((1 << signal.length) - 1):X}u"
        prefix = "      const auto bits = "
        lines += ["    {",
                  f"{prefix}{gather_expression(signal, unsigned_type(signal), prefix)};",
                  f"      // sign-extend: bit {signal.length - 1} is the sign, so copy it into the bits above",
                  f"      {target} = static_cast<{stype}>((bits & {sign_bit}) != 0 ? bits | {above} : bits);",
                  "    }"]
    return lines


def decode_expression(signal):
    expression = "static_cast<double>(raw)"
    if signal.factor.value != 1:
        expression += f" * {repr(signal.factor.double)}"
    if signal.offset.value:
        sign = "+" if signal.offset.value > 0 else "-"
        expression += f" {sign} {repr(abs(signal.offset.double))}"
    return expression


def encode_expression(signal):
    stype, width = cxx_type(signal)
    scaled = "value"
    if signal.offset.value:
        sign = "-" if signal.offset.value > 0 else "+"
        scaled = f"(value {sign} {repr(abs(signal.offset.double))})"
    if signal.factor.value != 1:
        scaled += f" / {repr(signal.factor.double)}"
    low, high = raw_limits(signal)
    if signal.signed:
        call = f"detail::round_saturate_i64({scaled}, {int_literal(low, True)}, {int_literal(high, True)})"
    else:
        call = f"detail::round_saturate_u64({scaled}, {int_literal(high, False)})"
    return call if width == 64 else f"static_cast<{stype}>({call})"


def in_range_conditions(signal):
    """Comparisons of the raw value against the DBC range (exact, done here), leaving out those
    the raw type makes always true (-Wtype-limits)."""
    bounds = in_range_raw_bounds(signal)
    if bounds is None:
        return []
    _, width = cxx_type(signal)
    type_low, type_high = ((-(1 << (width - 1)), (1 << (width - 1)) - 1) if signal.signed
                           else (0, (1 << width) - 1))
    low, high = math.ceil(bounds[0]), math.floor(bounds[1])
    conditions = []
    if low > type_low:
        conditions.append(f"raw >= {int_literal(low, signal.signed)}")
    if high < type_high:
        conditions.append(f"raw <= {int_literal(high, signal.signed)}")
    return conditions


def signal_function_lines(signal):
    stype, _ = cxx_type(signal)
    base = snake_case(signal.name)
    unit = f" {ascii_text(signal.unit)}" if signal.unit else ""
    sign = "-" if signal.offset.value < 0 else "+"
    conditions = in_range_conditions(signal)
    if conditions:
        parameter, body = "raw", " && ".join(conditions)
    else:  # [0|0] or a range as wide as the raw type: every raw value is in range
        parameter, body = "/*raw*/", "true"
    return [
        f"  // {signal.name}: raw * {signal.factor.text} {sign} {signal.offset.text.lstrip('+-')}{unit}, "
        f"in range [{signal.minimum.text}|{signal.maximum.text}]",
        f"  static constexpr double {base}_decode({stype} raw) noexcept {{",
        f"    return {decode_expression(signal)};",
        "  }",
        f"  static constexpr {stype} {base}_encode(double value) noexcept {{",
        *return_lines(encode_expression(signal)),
        "  }",
        f"  static constexpr bool {base}_is_in_range({stype} {parameter}) noexcept {{",
        f"    return {body};",
        "  }",
    ]


def return_lines(expression):
    """`return expression;`, broken after the outer cast's parenthesis if longer than 100 columns."""
    line = f"    return {expression};"
    if len(line) <= 100 or not expression.startswith("static_cast<"):
        return [line]
    cast, argument = expression.split("(", 1)
    return [f"    return {cast}(", f"        {argument};"]


def enum_lines(signal):
    stype, _ = cxx_type(signal)
    names = enumerator_names(signal.values)
    items = [f"{name} = {int_literal(raw, True)}" for name, (raw, _) in zip(names, signal.values)]
    head = f"  enum class {camel_case(signal.name)} : {stype} {{"
    one_line = f"{head} {', '.join(items)} }};"
    if len(one_line) <= 100:
        return [one_line]
    return [head] + [f"    {item}," for item in items] + ["  };"]


def signal_info(signal):
    return (f"{{{string_literal(signal.name)}, {string_literal(signal.unit)}, {repr(signal.factor.double)}, "
            f"{repr(signal.offset.double)}, {repr(signal.minimum.double)}, {repr(signal.maximum.double)}, "
            f"{signal.start}, {signal.length}, {str(signal.signed).lower()}, {str(signal.big_endian).lower()}}}")


def message_lines(message):
    struct = camel_case(message.name)
    cycle = f"every {message.cycle_time} ms" if message.cycle_time else "no cycle time"
    kind = " (extended)" if message.extended else ""
    lines = comment_lines(f"{message.name}: id 0x{message.can_id:X}{kind}, {message.dlc} bytes, {cycle}, "
                          f"sent by {message.sender}.", "")
    if message.comment:
        lines += comment_lines(message.comment, "")
    lines += [
        f"struct {struct} {{",
        f"  static constexpr std::uint32_t kId = 0x{message.can_id:X};",
        f"  static constexpr bool kExtended = {str(message.extended).lower()};",
        f"  static constexpr std::uint8_t kLength = {message.dlc};",
        f"  static constexpr std::uint32_t kCycleTimeMs = {message.cycle_time};",
        f"  static constexpr const char* kName = {string_literal(message.name)};",
        f"  static constexpr const char* kSender = {string_literal(message.sender)};",
    ]
    for signal in message.signals:
        if signal.values is not None:
            lines += [""] + comment_lines(f"Values of {signal.name} (VAL_).", "  ") + enum_lines(signal)
    lines += ["", "  // Raw signal values, the bits on the wire: physical = raw * factor + offset."]
    for signal in message.signals:
        if signal.comment:
            lines += comment_lines(signal.comment, "  ")
        lines.append(f"  {cxx_type(signal)[0]} {member_name(signal)} = 0;  // {sg_notation(signal)}")
    lines += [
        "",
        "  // Writes kLength bytes (unused bits 0). false (nothing written) if size < kLength.",
        "  constexpr bool pack(std::uint8_t* dst, std::size_t size) const noexcept {",
        "    if (size < kLength) {",
        "      return false;",
        "    }",
        "    for (std::size_t i = 0; i < kLength; ++i) {",
        "      dst[i] = 0;",
        "    }",
    ]
    for signal in message.signals:
        lines += pack_lines(signal)
    lines += [
        "    return true;",
        "  }",
        "",
        "  // false (nothing changed) if size < kLength. Signed signals are sign-extended.",
        "  constexpr bool unpack(const std::uint8_t* src, std::size_t size) noexcept {",
        "    if (size < kLength) {",
        "      return false;",
        "    }",
    ]
    for signal in message.signals:
        lines += unpack_lines(signal)
    lines += ["    return true;", "  }", ""]
    lines += ["  // encode: round((value - offset) / factor), saturated to what the signal's bits hold; NaN -> 0.",
              "  // is_in_range: the DBC's [min|max] on the physical value ([0|0]: any raw value)."]
    for signal in message.signals:
        lines += signal_function_lines(signal)
    lines += ["", "  // name, unit, factor, offset, min, max, start, length, is_signed, big_endian (DBC order)",
              "  static constexpr SignalInfo kSignals[] = {"]
    lines += [f"      {signal_info(signal)}," for signal in message.signals]
    lines += ["  };", f"  static constexpr std::size_t kNumSignals = {len(message.signals)};", "};", ""]
    return lines


DETAIL = """\
namespace detail {

// round(x), halves away from zero, saturated to [low, high]; NaN gives 0. Written out because
// std::round is not constexpr before C++23.
constexpr std::int64_t round_saturate_i64(double x, std::int64_t low, std::int64_t high) noexcept {
  if (x > static_cast<double>(low) && x < static_cast<double>(high)) {
    const auto whole = static_cast<std::int64_t>(x);  // truncates toward zero
    const double rest = x - static_cast<double>(whole);
    if (rest >= 0.5) {
      return whole + 1;
    }
    if (rest <= -0.5) {
      return whole - 1;
    }
    return whole;
  }
  if (x >= static_cast<double>(high)) {
    return high;
  }
  if (x <= static_cast<double>(low)) {
    return low;
  }
  return 0;  // NaN: every comparison above was false
}

// The same for unsigned signals: [0, high].
constexpr std::uint64_t round_saturate_u64(double x, std::uint64_t high) noexcept {
  if (x > 0.0 && x < static_cast<double>(high)) {
    const auto whole = static_cast<std::uint64_t>(x);
    return x - static_cast<double>(whole) >= 0.5 ? whole + 1 : whole;
  }
  if (x >= static_cast<double>(high)) {
    return high;
  }
  return 0;  // at or below 0, or NaN
}

}  // namespace detail
"""


def id_array_lines(name, messages):
    if not messages:
        return [f"// {name}: none (C++ has no empty arrays, so the array is left out)."]
    lines = [f"inline constexpr std::uint32_t {name}[] = {{"]
    lines += [f"    {camel_case(message.name)}::kId,  // 0x{message.can_id:X}" for message in messages]
    return lines + ["};"]


def render(dbc, messages, node, namespace, dbc_name):
    lines = [f"// Generated by {GENERATOR} from {dbc_name}; do not edit."]
    if dbc.comment:
        lines += comment_lines(dbc.comment, "")
    lines += [
        "#pragma once",
        "#include <cstddef>",
        "#include <cstdint>",
        "",
        f"namespace {namespace} {{",
        "",
        "// One signal's DBC definition, for code that walks a message's signals (logs, range tables).",
        "struct SignalInfo { const char* name; const char* unit; double factor, offset, min, max; "
        "std::uint8_t start, length; bool is_signed, big_endian; };",
        "",
        DETAIL,
    ]
    for message in messages:
        lines += message_lines(message)
    received = [m for m in messages if any(node in signal.receivers for signal in m.signals)]
    sent = [m for m in messages if m.sender == node or node in m.transmitters]
    if node in dbc.node_comments:
        lines += comment_lines(f"{node}: {dbc.node_comments[node]}", "")
    lines += comment_lines(f"The frames {node} receives (one of their signals names it as a receiver) and "
                           f"sends (it is the sender, or in BO_TX_BU_): ids without the extended flag, "
                           f"as each struct's kId.", "")
    lines += id_array_lines("kReceivedIds", received) + id_array_lines("kTransmittedIds", sent)
    lines += ["", f"}}  // namespace {namespace}", ""]
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Command line

def generate(text, node, namespace, dbc_name):
    dbc = Parser(tokenize(text)).parse()
    Checker(dbc).run()
    if node not in dict(dbc.nodes):
        raise DbcError(dbc.nodes_line or 1, f"node {node} (--node) is not in BU_")
    messages = [message for message in dbc.messages if message.is_frame]
    check_cxx_names(messages)
    header = render(dbc, messages, node, namespace, dbc_name)
    header.encode("ascii")  # a generator bug if not: every DBC text went through an escape
    return header


def read_text(path):
    """DBC files from Windows tools are often Latin-1 (cp1252) rather than UTF-8."""
    data = open(path, "rb").read()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def write_atomically(path, text):
    """A temporary file in the same directory, renamed over the target: a build never sees half a header."""
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=directory, prefix=".dbc_codegen.", suffix=".tmp")
    try:
        with os.fdopen(handle, "w", encoding="ascii", newline="\n") as file:
            file.write(text)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def main(argv=None):
    parser = argparse.ArgumentParser(description="Generate C++ CAN codecs from a DBC file.")
    parser.add_argument("--dbc", required=True, help="the DBC file")
    parser.add_argument("--node", required=True, help="the node whose received and sent ids to list")
    parser.add_argument("--namespace", default="lptn::can", help="C++ namespace of the generated code")
    parser.add_argument("--out", required=True, help="the header to write")
    args = parser.parse_args(argv)
    if not re.fullmatch(r"[A-Za-z_]\w*(::[A-Za-z_]\w*)*", args.namespace, re.ASCII):
        parser.error(f"--namespace {args.namespace!r} is not a C++ namespace name")
    try:
        header = generate(read_text(args.dbc), args.node, args.namespace, os.path.basename(args.dbc))
    except OSError as error:
        print(f"{args.dbc}:0: cannot read the file ({error.strerror})", file=sys.stderr)
        return 1
    except DbcError as error:
        print(f"{args.dbc}:{error.line}: {error.reason}", file=sys.stderr)
        return 1
    write_atomically(args.out, header)
    return 0


if __name__ == "__main__":
    sys.exit(main())
