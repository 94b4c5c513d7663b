#!/usr/bin/env python3
"""Generates the C++ CAN codecs (one header) from a DBC file.

    dbc_codegen.py --dbc lptn.dbc --node LPTN --namespace lptn::can --out DIR/lptn/can/lptn_frames.hpp [--werror]

The DBC is the single source of truth for every CAN frame, so the build runs this script whenever
the DBC changes. It reads DBC files as the industry writes them: what leaves every frame
decodable (a range its bits cannot hold, a node missing from BU_, a message without signals, a bare
id above 0x7FF, ...) is a warning, `FILE:LINE: warning: reason` on stderr, and the header is
written. What would make a frame undecodable, or the generated code wrong, stops the build: one
line `FILE:LINE: reason` on stderr, exit status 1, and no output file. With --werror (our own
DBC files) the first warning stops the build in the same way.

Supported beyond classic CAN: extended ids (the 0x80000000 flag, or a bare id above 0x7FF), CAN FD
lengths up to 64 bytes, and simple multiplexing (one multiplexor `M` per message, signals `m<N>`,
SG_MUL_VAL_ ranges on that multiplexor).

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

GENERATOR = "can/codecs/dbc_codegen.py"
NO_NODE = "Vector__XXX"  # what DBC tools write where a sender or receiver is "none"
# Vector tools park signals that belong to no frame in this pseudo message; it is not a frame.
INDEPENDENT_SIGNALS_ID = 0xC0000000
EXTENDED_FLAG = 0x80000000


class DbcError(Exception):
    def __init__(self, line, reason):
        super().__init__(reason)
        self.line = line
        self.reason = reason


class Warnings:
    """What the generator reads past: (line, reason), printed once the header is written."""

    def __init__(self):
        self.items = []

    def add(self, line, reason):
        self.items.append((line, reason))

    def sorted(self):
        return sorted(self.items, key=lambda item: item[0])


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
  | (?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?(?![A-Za-z0-9_.]))
  | (?P<ident>[A-Za-z_][A-Za-z0-9_]*|[0-9]+[A-Za-z_][A-Za-z0-9_]*)
  | (?P<punct>[:;|@(),\[\]+-])
""", re.VERBOSE | re.DOTALL)


def tokenize(text):
    """Signs are separate tokens (the parser joins them to numbers): `@1-` is `@`, `1`, `-`.
    Names may start with a digit (`2017_5`, `0_COUNTER`: real files have them)."""
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
    multiplexor: bool = False  # `M`: its value says which `m<N>` signals the frame carries
    mux_ranges: list = None  # `m<N>`: [(low, high)] of multiplexor values that carry it; else None
    range_ignored: bool = False  # [min|max] cannot be right: _is_in_range() is always true

    @property
    def multiplexed(self):
        return self.mux_ranges is not None


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
    bare_extended: bool = False  # an id above 0x7FF without the flag, taken as extended
    left_out: bool = False  # no CAN frame can have its id: read, checked for references, not generated
    left_out_signals: list = field(default_factory=list)  # signals outside the frame: not generated

    @property
    def extended(self):
        return bool(self.dbc_id & EXTENDED_FLAG) or self.bare_extended

    @property
    def is_frame(self):
        return self.dbc_id != INDEPENDENT_SIGNALS_ID

    @property
    def generated(self):
        return self.is_frame and not self.left_out

    @property
    def can_id(self):
        return self.dbc_id & ~EXTENDED_FLAG

    @property
    def multiplexor(self):
        return next((signal for signal in self.signals if signal.multiplexor), None)


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
class MuxValuesStmt:
    """SG_MUL_VAL_ id signal multiplexor low-high, ...;"""
    line: int
    message_id: int
    signal: str
    multiplexor: str
    ranges: list


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
    def __init__(self, tokens, warnings=None):
        self.warnings = warnings if warnings is not None else Warnings()
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
        """A whole number; `1e+09` is one (tools write attribute limits so)."""
        start = self.peek()
        number = self.number(what)
        if number.value.denominator != 1 or "." in number.text:
            self.fail(start, what)
        return int(number.value)

    def natural(self, what):
        """A count or a position: an integer written in digits, without a sign."""
        if self.at_punct("-") or self.at_punct("+"):
            self.fail(self.peek(), what)
        start = self.peek()
        value = self.integer(what)
        if not start.text.isdigit():
            self.fail(start, what)
        return value

    def value(self, what):
        """An attribute value: a number or a string."""
        if self.peek().kind == "string":
            return self.string(what)
        return self.number(what).value

    def at_next_section(self):
        """The next token starts a section on a later line: where a forgotten ';' would have been."""
        token = self.peek()
        previous = self.tokens[self.pos - 1] if self.pos else token
        return (token.kind == "eof" or token.kind == "ident" and token.line > previous.line
                and (token.text in self.SECTIONS or token.text in SKIPPED_SECTIONS))

    def missing_semicolon(self, section):
        """A statement the next section keyword ends as clearly as ';' would: read, with a warning."""
        if not self.at_next_section():
            return False
        line = self.tokens[self.pos - 1].line if self.pos else self.peek().line
        self.warnings.add(line, f"expected ';' at the end of {section}, found {_describe(self.peek())}; "
                                f"read as if it were there")
        return True

    def end(self, section):
        if not self.at_punct(";") and self.missing_semicolon(section):
            return
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
        if dbc_id >= 1 << 32:
            raise DbcError(keyword.line, f"message id {dbc_id} does not fit in 32 bits")
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
        multiplexor, mux_ranges = False, None
        if self.peek().kind == "ident":  # the multiplex indicator: M, m<N> or m<N>M
            indicator = self.take().text
            match = re.fullmatch(r"m([0-9]+)(M?)", indicator)
            if indicator == "M":
                multiplexor = True
            elif match and match.group(2):
                raise DbcError(keyword.line, f"signal {name}: extended multiplexing ({indicator}: a multiplexed "
                                             "multiplexor) is not supported, only one multiplexor per message")
            elif match:
                mux_ranges = [(int(match.group(1)), int(match.group(1)))]
            elif indicator == "m":
                multiplexor = True
                self.warnings.add(keyword.line, f"signal {name}: multiplex indicator 'm' without a value; "
                                                "read as 'M' (the multiplexor)")
            else:
                raise DbcError(keyword.line, f"signal {name}: expected ':' or a multiplex indicator "
                                             f"(M or m<N>), found '{indicator}'")
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
            minimum, maximum, unit, receivers, multiplexor=multiplexor, mux_ranges=mux_ranges))

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
            if pairs and self.missing_semicolon(section):
                break
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
        message_id = self.integer("a message id after SG_MUL_VAL_")
        signal = self.ident("a signal name")
        multiplexor = self.ident("the multiplexor's name")
        ranges = []
        while True:
            low = self.natural("the low end of a multiplexor value range")
            self.punct("-", "between the ends of a multiplexor value range")
            high = self.natural("the high end of a multiplexor value range")
            if low > high:
                raise DbcError(keyword.line, f"multiplexor value range {low}-{high} is empty")
            ranges.append((low, high))
            if not self.accept_punct(","):
                break
        self.end("SG_MUL_VAL_")
        self.dbc.statements.append(MuxValuesStmt(keyword.line, message_id, signal, multiplexor, ranges))

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
    """Exact raw bounds of the DBC's physical [min|max], or None for [0|0] (no range) and for a
    range the checker found cannot be right."""
    if signal.minimum.value == 0 and signal.maximum.value == 0 or signal.range_ignored:
        return None
    factor, offset = signal.factor.value, signal.offset.value
    ends = sorted(((signal.minimum.value - offset) / factor, (signal.maximum.value - offset) / factor))
    return ends[0], ends[1]


def mux_values_meet(one, other):
    """Can a frame carry both signals? Yes unless both are multiplexed on disjoint values."""
    if not one.multiplexed or not other.multiplexed:
        return True
    return any(a_low <= b_high and b_low <= a_high
               for a_low, a_high in one.mux_ranges for b_low, b_high in other.mux_ranges)


def format_ranges(ranges):
    return ", ".join(str(low) if low == high else f"{low}..{high}" for low, high in ranges)


# ---------------------------------------------------------------------------------------------
# Validation

FD_LENGTHS = (12, 16, 20, 24, 32, 48, 64)  # the CAN FD frame lengths above 8 bytes


class Checker:
    def __init__(self, dbc, warnings=None, node=None):
        self.dbc = dbc
        self.node = node  # the node the header is for (--node)
        self.warnings = warnings if warnings is not None else Warnings()
        self.nodes = {}
        self.unknown_nodes = {}
        self.by_id = {}
        self.seen_statements = {}

    def warn(self, line, reason):
        self.warnings.add(line, reason)

    def run(self):
        self.check_nodes()
        self.check_messages()
        for statement in self.dbc.statements:
            self.RESOLVERS[type(statement)](self, statement)
        for message in self.dbc.messages:
            if message.generated:
                self.check_layout(message)
        self.apply_default_cycle_time()

    def check_nodes(self):
        if self.dbc.nodes_line is None:
            self.warn(1, "the file has no BU_ section; senders and receivers are not checked")
        for name, line in self.dbc.nodes:
            if name in self.nodes:
                self.warn(line, f"node {name} is listed twice in BU_ (first on line {self.nodes[name]})")
                continue
            self.nodes[name] = line

    def check_node(self, name, line, role):
        """One warning per unknown node, where the file first names it."""
        if name == NO_NODE or name in self.nodes or self.dbc.nodes_line is None:
            return
        if name not in self.unknown_nodes:
            self.unknown_nodes[name] = [(line, role)]
            self.warn(line, f"{role} '{name}' is not a node in BU_")
        else:
            self.unknown_nodes[name].append((line, role))

    def check_messages(self):
        by_name = {}
        by_frame_id = {}
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
            self.check_id(message)
            if message.left_out:
                continue
            key = (message.extended, message.can_id)
            if key in by_frame_id:
                first = by_frame_id[key]
                raise DbcError(message.line, f"message {message.name}: {'extended' if message.extended else 'standard'} "
                                             f"id 0x{message.can_id:X} is already used by {first.name} on line {first.line}")
            by_frame_id[key] = message
            self.check_message(message)

    def check_id(self, message):
        """Flagged ids fit in 29 bits; a bare id above 0x7FF is taken as extended (tools write them
        so); an id no CAN frame can have leaves its message out of the header."""
        where = f"message {message.name}"
        if message.dbc_id & EXTENDED_FLAG:
            if message.can_id > 0x1FFFFFFF:
                message.left_out = True
                self.warn(message.line, f"{where}: extended id 0x{message.can_id:X} does not fit in 29 bits; "
                                        "no CAN frame has it, so the message is left out")
        elif message.can_id > 0x1FFFFFFF:
            message.left_out = True
            self.warn(message.line, f"{where}: id {message.dbc_id} (0x{message.dbc_id:X}) fits neither 11 nor "
                                    "29 bits and has no extended flag (0x80000000); no CAN frame has it, so "
                                    "the message is left out")
        elif message.can_id > 0x7FF:
            message.bare_extended = True
            self.warn(message.line, f"{where}: id 0x{message.can_id:X} does not fit in 11 bits and has no "
                                    "extended flag (0x80000000); taken as a 29-bit extended id")

    def check_message(self, message):
        where = f"message {message.name}"
        if message.dlc > 64:
            raise DbcError(message.line, f"{where}: length {message.dlc} is more than 64 bytes, CAN FD's "
                                         "longest frame")
        if message.dlc > 8 and message.dlc not in FD_LENGTHS:
            fd_length = next(length for length in FD_LENGTHS if length > message.dlc)
            self.warn(message.line, f"{where}: length {message.dlc} is not a CAN FD frame length (a frame "
                                    f"carrying it is {fd_length} bytes long); {message.dlc} bytes are packed "
                                    "and unpacked")
        self.check_node(message.sender, message.line, f"{where}: sender")
        if not message.signals:
            data = f"packs {message.dlc} zero bytes" if message.dlc else "has no data"
            self.warn(message.line, f"{where} has no signals; its struct {data}")
        names = {}
        for signal in message.signals:
            if signal.name in names:
                raise DbcError(signal.line, f"signal {signal.name} appears twice in message {message.name} "
                                            f"(first on line {names[signal.name]})")
            names[signal.name] = signal.line
            if not self.check_signal(message, signal):
                message.left_out_signals.append(signal)
        message.signals = [signal for signal in message.signals if signal not in message.left_out_signals]
        multiplexor = None
        for signal in message.signals:
            if signal.multiplexor:
                if multiplexor is not None:
                    raise DbcError(signal.line, f"signal {signal.name}: message {message.name} already has a "
                                                f"multiplexor ({multiplexor.name}, line {multiplexor.line}); "
                                                "extended multiplexing is not supported")
                multiplexor = signal
        for signal in message.signals:
            if signal.multiplexed and multiplexor is None:
                raise DbcError(signal.line, f"signal {signal.name} is multiplexed (m{signal.mux_ranges[0][0]}) "
                                            f"but message {message.name} has no multiplexor (M)")

    def check_layout(self, message):
        """Two signals may share frame bits only if no multiplexor value carries both."""
        multiplexor = message.multiplexor
        if multiplexor is not None:
            self.check_mux_values(message, multiplexor)
        owners = {}
        for signal in message.signals:
            overlapped = {}
            for bit in frame_bits(signal):
                for other in owners.get(bit, []):
                    if mux_values_meet(signal, other):
                        overlapped.setdefault(other.name, bit)
                owners.setdefault(bit, []).append(signal)
            if overlapped:
                # Each signal still reads its own bits; only a frame packed with both is ambiguous.
                others = ", ".join(f"{other} (frame bit {bit})" for other, bit in overlapped.items())
                self.warn(signal.line, f"signal {signal.name} overlaps signal{'s' if len(overlapped) > 1 else ''} "
                                       f"{others} in message {message.name}; each unpacks from the shared bits, "
                                       "pack() ORs them together")

    def check_mux_values(self, message, multiplexor):
        low, high = raw_limits(multiplexor)
        for signal in message.signals:
            if signal.multiplexed and all(r_high < low or r_low > high for r_low, r_high in signal.mux_ranges):
                self.warn(signal.line, f"signal {signal.name}: multiplexor {multiplexor.name} "
                                       f"({multiplexor.length} bits, raw {low}..{high}) never takes "
                                       f"{format_ranges(signal.mux_ranges)}; the signal is never in the frame")

    def check_signal(self, message, signal):
        where = f"signal {signal.name}"
        if not 1 <= signal.length <= 64:
            raise DbcError(signal.line, f"{where}: length {signal.length} is not in 1..64")
        if signal.factor.value == 0:
            raise DbcError(signal.line, f"{where}: factor 0 (every raw value would decode to the offset)")
        for receiver in signal.receivers:
            self.check_node(receiver, signal.line, f"{where}: receiver")
        if max(frame_bits(signal)) >= 8 * message.dlc:
            # The file contradicts itself (the length or the layout is wrong) and nothing tells
            # which. The node the header is for cannot do without a signal it sends or receives:
            # an error. A signal only other nodes use is left out, with a warning.
            order = "big-endian" if signal.big_endian else "little-endian"
            overflow = (f"{where} ({order}, start bit {signal.start}, {signal.length} bits) "
                        f"overflows its {message.dlc}-byte frame")
            if self.node is None or self.node != NO_NODE and (self.node == message.sender
                                                              or self.node in signal.receivers):
                raise DbcError(signal.line, overflow)
            self.warn(signal.line, f"{overflow}; {self.node} neither sends nor receives it, so it is left out")
            return False
        self.check_range(signal)
        return True

    def check_range(self, signal):
        """A range that cannot be right leaves decoding alone: a warning, and _is_in_range() says
        what is written in the comment above it."""
        where = f"signal {signal.name}: range [{signal.minimum.text}|{signal.maximum.text}]"
        if signal.minimum.value > signal.maximum.value:
            signal.range_ignored = True
            self.warn(signal.line, f"{where}: minimum {signal.minimum.text} is greater than maximum "
                                   f"{signal.maximum.text}; the range is ignored (every raw value is in range)")
            return
        bounds = in_range_raw_bounds(signal)
        if bounds is None:
            return
        low, high = raw_limits(signal)
        if bounds[0] < low or bounds[1] > high:
            kind = "signed" if signal.signed else "unsigned"
            self.warn(signal.line, f"{where} needs raw values {_fmt(bounds[0])}..{_fmt(bounds[1])} but "
                                   f"{signal.length} {kind} bits cannot represent them (they hold {low}..{high}); "
                                   "the range is checked within what the bits hold")
        if math.ceil(bounds[0]) > math.floor(bounds[1]) or math.ceil(bounds[0]) > high \
                or math.floor(bounds[1]) < low:
            signal.range_ignored = True
            self.warn(signal.line, f"{where} contains no raw value the signal can hold; the range is ignored "
                                   "(every raw value is in range)")

    # -- statements that refer to other objects
    # A statement about a message or signal the file does not define describes nothing that is
    # on the bus: it is read past with a warning (message() and signal() give None).
    def message(self, message_id, line, statement):
        if message_id not in self.by_id:
            self.warn(line, f"no message has id {message_id}; the {statement} is ignored")
            return None
        return self.by_id[message_id]

    def signal(self, message_id, name, line, statement):
        message = self.message(message_id, line, statement)
        if message is None:
            return None, None
        for signal in message.signals + message.left_out_signals:
            if signal.name == name:
                return message, signal
        self.warn(line, f"message {message.name} has no signal {name}; the {statement} is ignored")
        return None, None

    def once(self, what, key, line):
        """A second statement for the same thing: the later one is used."""
        if key in self.seen_statements:
            self.warn(line, f"second {what} (the first is on line {self.seen_statements[key]}); this one is used")
        self.seen_statements[key] = line

    def resolve_comment(self, stmt):
        target = {"BU_": f"node {stmt.key}", "BO_": f"message {stmt.key}",
                  "SG_": f"signal {stmt.key[1]} of message {stmt.key[0]}" if stmt.kind == "SG_" else "",
                  "EV_": f"environment variable {stmt.key}", "": "the network"}[stmt.kind]
        self.once(f"comment for {target}", ("CM_", stmt.kind, stmt.key), stmt.line)
        if stmt.kind == "":
            self.dbc.comment = stmt.text
        elif stmt.kind == "BU_":
            self.check_node(stmt.key, stmt.line, "CM_ BU_:")
            self.dbc.node_comments[stmt.key] = stmt.text
        elif stmt.kind == "BO_":
            message = self.message(stmt.key, stmt.line, "CM_")
            if message is not None:
                message.comment = stmt.text
        elif stmt.kind == "SG_":
            signal = self.signal(*stmt.key, stmt.line, "CM_")[1]
            if signal is not None:
                signal.comment = stmt.text

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
            message = self.message(stmt.key, stmt.line, "BA_")
            if message is not None and stmt.name == "GenMsgCycleTime":
                message.cycle_time = cycle_time(stmt.value, stmt.line)
        elif stmt.kind == "SG_":
            self.signal(*stmt.key, stmt.line, "BA_")

    def resolve_values(self, stmt):
        self.once(f"VAL_ for signal {stmt.signal}", ("VAL_", stmt.message_id, stmt.signal), stmt.line)
        message, signal = self.signal(stmt.message_id, stmt.signal, stmt.line, "VAL_")
        if message is None or not message.generated or signal in message.left_out_signals:
            return  # never checked, nor generated
        low, high = raw_limits(signal)
        pairs = []
        for raw, description in stmt.pairs:
            if low <= raw <= high:
                pairs.append((raw, description))
            else:
                self.warn(stmt.line, f"VAL_ value {raw} does not fit signal {signal.name} (raw {low}..{high}); "
                                     "it is left out of the enum")
        signal.values = pairs or None

    def resolve_value_type(self, stmt):
        message, signal = self.signal(stmt.message_id, stmt.signal, stmt.line, "SIG_VALTYPE_")
        if message is not None and message.generated and signal not in message.left_out_signals \
                and stmt.value_type != 0:
            raise DbcError(stmt.line, f"signal {signal.name}: IEEE float signals (SIG_VALTYPE_ "
                                      f"{stmt.value_type}) are not supported")

    def resolve_transmitters(self, stmt):
        message = self.message(stmt.message_id, stmt.line, "BO_TX_BU_")
        if message is None:
            return
        for node in stmt.nodes:
            self.check_node(node, stmt.line, f"message {message.name}: transmitter")
        message.transmitters.extend(stmt.nodes)

    def resolve_mux_values(self, stmt):
        """SG_MUL_VAL_: the multiplexor values that carry a signal, for the message's only
        multiplexor (what simple multiplexing writes; the m<N> value is replaced)."""
        self.once(f"SG_MUL_VAL_ for signal {stmt.signal}", ("SG_MUL_VAL_", stmt.message_id, stmt.signal),
                  stmt.line)
        message, signal = self.signal(stmt.message_id, stmt.signal, stmt.line, "SG_MUL_VAL_")
        if message is None or self.signal(stmt.message_id, stmt.multiplexor, stmt.line, "SG_MUL_VAL_")[1] is None:
            return
        if not message.generated or signal in message.left_out_signals:
            return
        multiplexor = message.multiplexor
        if not signal.multiplexed:
            raise DbcError(stmt.line, f"SG_MUL_VAL_: signal {signal.name} is not multiplexed (m<N>)")
        if multiplexor is None or multiplexor.name != stmt.multiplexor:
            raise DbcError(stmt.line, f"SG_MUL_VAL_: {stmt.multiplexor} is not the multiplexor (M) of message "
                                      f"{message.name}; extended multiplexing is not supported")
        signal.mux_ranges = stmt.ranges

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
        MuxValuesStmt: resolve_mux_values,
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
    """TC_Electrical -> TcElectrical: all-capital words become Capitalised. A name that starts
    with a digit (2017_5) gets an N in front (N20175): C++ names cannot."""
    parts = [part for part in name.split("_") if part]
    text = "".join(part.capitalize() if part.isupper() else part[0].upper() + part[1:] for part in parts)
    return "N" + text if text[:1].isdigit() else text


def snake_case(name):
    """MotorSpeed -> motor_speed, ABSActive -> abs_active; 0_COUNTER -> n_0_counter."""
    text = re.sub(r"([A-Z]+)([A-Z][a-z])", r"\1_\2", name)
    text = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", text)
    text = re.sub(r"_+", "_", text).strip("_").lower()
    return "n_" + text if text[:1].isdigit() else text


def base_name(signal):
    """The signal's name in C++ (snake case), as check_cxx_names() chose it."""
    return getattr(signal, "cxx_base", None) or snake_case(signal.name)


def member_name(signal):
    base = base_name(signal)
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


def _claim_free(names, candidates, derived, owner, line, warnings):
    """The first of `candidates` whose derived names (derived(candidate)) are all free; a warning
    says when it is not the first. The names are C++'s, so two DBC names may meet in one."""
    first = None
    for candidate in candidates:
        wanted = derived(candidate)
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", wanted[0]):
            raise DbcError(line, f"{owner} gives no valid C++ name ('{wanted[0]}')")
        taken = next((name for name in wanted if name in names), None)
        if taken is None:
            if first is not None:
                warnings.add(line, f"{owner}: its C++ name '{first[0]}' clashes with {first[1]}; "
                                   f"named '{wanted[0]}' instead")
            for name in wanted:
                names[name] = owner
            return candidate
        if first is None:
            first = (taken, names[taken])
    raise DbcError(line, f"{owner}: its C++ name '{first[0]}' clashes with {first[1]}")


def _numbered(base, first_suffixes=()):
    yield base
    yield from (base + suffix for suffix in first_suffixes)
    yield from (f"{base}_{n}" for n in range(2, 100))


def check_cxx_names(messages, warnings=None):
    """Names the C++ code gives each message (cxx_name), signal (cxx_base, cxx_enum) and value.
    Different DBC names can meet in C++ (TC_Speed and TcSpeed, Speed and speed_decode, a signal
    GEAR with values in a message GEAR): the later one is renamed, with a warning."""
    warnings = warnings if warnings is not None else Warnings()
    global_names = {name: "a name the header defines" for name in NAMESPACE_NAMES}
    for message in messages:
        message.cxx_name = _claim_free(global_names, _numbered(camel_case(message.name)), lambda name: [name],
                                       f"message {message.name}", message.line, warnings)
        members = {name: "a name the header defines" for name in STRUCT_CONSTANTS}
        members[message.cxx_name] = "the struct's own name"
        for signal in message.signals:
            owner = f"signal {signal.name}"

            def derived(base, signal=signal):
                member = base + "_" if base in CXX_KEYWORDS or base in PACK_LOCALS else base
                names = [member, base + "_decode", base + "_encode", base + "_is_in_range"]
                return names + [base + "_is_present"] if signal.multiplexed else names

            signal.cxx_base = _claim_free(members, _numbered(snake_case(signal.name)), derived, owner, signal.line,
                                          warnings)
            if signal.values is not None:
                signal.cxx_enum = _claim_free(members, _numbered(camel_case(signal.name), ("Values",)),
                                              lambda name: [name], f"the values (VAL_) of {signal.name}",
                                              signal.line, warnings)
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
    base = base_name(signal)
    unit = f" {ascii_text(signal.unit)}" if signal.unit else ""
    sign = "-" if signal.offset.value < 0 else "+"
    conditions = in_range_conditions(signal)
    if conditions:
        parameter, body = "raw", " && ".join(conditions)
    else:  # [0|0] or a range as wide as the raw type: every raw value is in range
        parameter, body = "/*raw*/", "true"
    return [
        f"  // {signal.name}: raw * {signal.factor.text} {sign} {signal.offset.text.lstrip('+-')}{unit}, "
        f"in range [{signal.minimum.text}|{signal.maximum.text}]{' (ignored: it cannot be right)' if signal.range_ignored else ''}",
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
    head = f"  enum class {signal.cxx_enum} : {stype} {{"
    one_line = f"{head} {', '.join(items)} }};"
    if len(one_line) <= 100:
        return [one_line]
    return [head] + [f"    {item}," for item in items] + ["  };"]


def signal_info(signal):
    return (f"{{{string_literal(signal.name)}, {string_literal(signal.unit)}, {repr(signal.factor.double)}, "
            f"{repr(signal.offset.double)}, {repr(signal.minimum.double)}, {repr(signal.maximum.double)}, "
            f"{signal.start}, {signal.length}, {str(signal.signed).lower()}, {str(signal.big_endian).lower()}}}")


def present_condition(signal, multiplexor):
    """The C++ condition under which the frame carries a multiplexed signal, comparing the
    multiplexor's raw member only where its type does not make the comparison constant."""
    _, width = cxx_type(multiplexor)
    type_low, type_high = ((-(1 << (width - 1)), (1 << (width - 1)) - 1) if multiplexor.signed
                           else (0, (1 << width) - 1))
    raw_low, raw_high = raw_limits(multiplexor)
    mux, signed = member_name(multiplexor), multiplexor.signed
    alternatives = []
    for low, high in signal.mux_ranges:
        low, high = max(low, raw_low), min(high, raw_high)
        if low > high:
            continue
        if low == high:
            alternatives.append(f"{mux} == {int_literal(low, signed)}")
            continue
        ends = []
        if low > type_low:
            ends.append(f"{mux} >= {int_literal(low, signed)}")
        if high < type_high:
            ends.append(f"{mux} <= {int_literal(high, signed)}")
        if not ends:
            return "true"
        alternatives.append(" && ".join(ends))
    if not alternatives:
        return "false"
    if len(alternatives) == 1:
        return alternatives[0]
    return " || ".join(f"({alternative})" if "&&" in alternative else alternative
                       for alternative in alternatives)


def indented(lines, extra="  "):
    return [extra + line if line else line for line in lines]


def message_lines(message):
    struct = message.cxx_name
    cycle = f"every {message.cycle_time} ms" if message.cycle_time else "no cycle time"
    kind = " (extended)" if message.extended else ""
    lines = comment_lines(f"{message.name}: id 0x{message.can_id:X}{kind}, {message.dlc} bytes, {cycle}, "
                          f"sent by {message.sender}.", "")
    if message.comment:
        lines += comment_lines(message.comment, "")
    multiplexor = message.multiplexor
    if multiplexor is not None:
        lines += comment_lines(f"Multiplexed: {multiplexor.name} says which of the signals marked m<N> the frame "
                               f"carries. unpack() reads those it carries and zeroes the others; pack() writes "
                               f"those the multiplexor's value selects; NAME_is_present() tells which.", "")
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
    if message.signals:
        lines += ["", "  // Raw signal values, the bits on the wire: physical = raw * factor + offset."]
    for signal in message.signals:
        if signal.comment:
            lines += comment_lines(signal.comment, "  ")
        note = ""
        if signal.multiplexor:
            note = ", the multiplexor"
        elif signal.multiplexed:
            note = f", in the frame when {multiplexor.name} is {format_ranges(signal.mux_ranges)}"
        lines.append(f"  {cxx_type(signal)[0]} {member_name(signal)} = 0;  // {sg_notation(signal)}{note}")
    plain = [signal for signal in message.signals if not signal.multiplexed]
    muxed = [signal for signal in message.signals if signal.multiplexed]
    if muxed:
        lines += ["", f"  // Whether the frame carries the signal: {multiplexor.name}'s value selects it."]
        for signal in muxed:
            lines += [f"  constexpr bool {base_name(signal)}_is_present() const noexcept {{",
                      f"    return {present_condition(signal, multiplexor)};",
                      "  }"]
    if message.dlc == 0:
        lines += [
            "",
            "  // A frame without data: nothing to write or read.",
            "  constexpr bool pack(std::uint8_t* /*dst*/, std::size_t /*size*/) const noexcept { return true; }",
            "  constexpr bool unpack(const std::uint8_t* /*src*/, std::size_t /*size*/) noexcept { return true; }",
        ]
    else:
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
        for signal in plain:
            lines += pack_lines(signal)
        for signal in muxed:
            lines += [f"    if ({base_name(signal)}_is_present()) {{"] + indented(pack_lines(signal)) + ["    }"]
        lines += [
            "    return true;",
            "  }",
            "",
            "  // false (nothing changed) if size < kLength. Signed signals are sign-extended.",
            f"  constexpr bool unpack(const std::uint8_t* {'src' if message.signals else '/*src*/'}, "
            "std::size_t size) noexcept {",
            "    if (size < kLength) {",
            "      return false;",
            "    }",
        ]
        for signal in plain:
            lines += unpack_lines(signal)
        for signal in muxed:
            lines += [f"    if ({base_name(signal)}_is_present()) {{"] + indented(unpack_lines(signal))
            lines += ["    } else {", f"      {member_name(signal)} = 0;", "    }"]
        lines += ["    return true;", "  }"]
    lines += [""]
    if message.signals:
        lines += ["  // encode: round((value - offset) / factor), saturated to what the signal's bits hold; NaN -> 0.",
                  "  // is_in_range: the DBC's [min|max] on the physical value ([0|0]: any raw value)."]
    for signal in message.signals:
        lines += signal_function_lines(signal)
    if message.signals:
        lines += ["", "  // name, unit, factor, offset, min, max, start, length, is_signed, big_endian (DBC order)",
                  "  static constexpr SignalInfo kSignals[] = {"]
        lines += [f"      {signal_info(signal)}," for signal in message.signals]
        lines += ["  };"]
    else:
        lines += ["  // No signals (C++ has no empty arrays): kSignals points nowhere."]
        lines += ["  static constexpr const SignalInfo* kSignals = nullptr;"]
    lines += [f"  static constexpr std::size_t kNumSignals = {len(message.signals)};", "};", ""]
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
    lines += [f"    {message.cxx_name}::kId,  // 0x{message.can_id:X}" for message in messages]
    return lines + ["};"]


def signal_info_lines(messages):
    """SignalInfo, with a 16-bit start where a CAN FD frame of more than 32 bytes has start bits
    above 255 (the classic layout otherwise, as every header had it before CAN FD)."""
    if all(message.dlc <= 32 for message in messages):
        return ["struct SignalInfo { const char* name; const char* unit; double factor, offset, min, max; "
                "std::uint8_t start, length; bool is_signed, big_endian; };"]
    return ["// CAN FD frames up to 64 bytes: start bits up to 511.",
            "struct SignalInfo { const char* name; const char* unit; double factor, offset, min, max; "
            "std::uint16_t start; std::uint8_t length; bool is_signed, big_endian; };"]


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
        *signal_info_lines(messages),
        "",
        DETAIL,
    ]
    for message in messages:
        lines += message_lines(message)
    received = [m for m in messages if any(node in signal.receivers for signal in m.signals)]
    sent = [m for m in messages if m.sender == node or node in m.transmitters]
    if node == NO_NODE:  # a header for the whole bus (a logger's): no node of its own
        received, sent = [], []
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

def generate(text, node, namespace, dbc_name, warnings=None):
    """The header's text; what the generator read past goes to `warnings` (a Warnings)."""
    warnings = warnings if warnings is not None else Warnings()
    dbc = Parser(tokenize(text), warnings).parse()
    Checker(dbc, warnings, node).run()
    if dbc.nodes_line is not None and node != NO_NODE and node not in dict(dbc.nodes):
        raise DbcError(dbc.nodes_line or 1, f"node {node} (--node) is not in BU_")
    messages = [message for message in dbc.messages if message.generated]
    check_cxx_names(messages, warnings)
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
    parser.add_argument("--node", required=True,
                        help=f"the node whose received and sent ids to list ({NO_NODE}: none, a header for "
                             "the whole bus)")
    parser.add_argument("--namespace", default="lptn::can", help="C++ namespace of the generated code")
    parser.add_argument("--out", required=True, help="the header to write")
    parser.add_argument("--werror", action="store_true",
                        help="a warning stops the build as an error does (for DBC files we write ourselves)")
    args = parser.parse_args(argv)
    if not re.fullmatch(r"[A-Za-z_]\w*(::[A-Za-z_]\w*)*", args.namespace, re.ASCII):
        parser.error(f"--namespace {args.namespace!r} is not a C++ namespace name")
    warnings = Warnings()
    try:
        header = generate(read_text(args.dbc), args.node, args.namespace, os.path.basename(args.dbc), warnings)
    except OSError as error:
        print(f"{args.dbc}:0: cannot read the file ({error.strerror})", file=sys.stderr)
        return 1
    except DbcError as error:
        print(f"{args.dbc}:{error.line}: {error.reason}", file=sys.stderr)
        return 1
    if args.werror and warnings.items:
        line, reason = warnings.sorted()[0]
        print(f"{args.dbc}:{line}: {reason} [--werror]", file=sys.stderr)
        return 1
    write_atomically(args.out, header)
    for line, reason in warnings.sorted():
        print(f"{args.dbc}:{line}: warning: {reason}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
