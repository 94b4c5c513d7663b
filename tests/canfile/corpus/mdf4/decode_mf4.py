#!/usr/bin/env python3
"""A second, deliberately simple reading of the MDF4 bus logging files in this directory, written
apart from can/canfile/mdf4_read.cpp (channel by channel, as a generic MDF reader would: every
channel of a group decoded by name into columns, then the columns combined into frames), to make
the reference frames *.frames.txt that tests/canfile/test_mdf4.cpp compares lptn's reader with.

It reads only what these files use: unsorted data groups in one DT block (unfinalized: to the
end of the file) with record ids of 1 byte, or sorted ones (one channel group, no record ids);
fixed data bytes, or VLSD in a channel group or in one SD block; linear and value-to-value
conversions; virtual channels. One line per frame, in time order (equal times: in file order):

    SECONDS.MICROS CHANNEL ID(hex) EXTENDED REMOTE ERROR FD LENGTH DATA(hex)

    python3 decode_mf4.py FILE.MF4 > FILE.frames.txt
"""
import struct
import sys

data = open(sys.argv[1], "rb").read()


def block(at):
    ident, length, nlinks = data[at:at + 4], *struct.unpack_from("<QQ", data, at + 8)
    links = struct.unpack_from("<%dQ" % nlinks, data, at + 24)
    return ident, length, links, at + 24 + 8 * nlinks


def text(at):
    if not at:
        return ""
    _, length, _, body = block(at)
    return data[body:at + length].split(b"\0")[0].decode()


def conversion(at):
    if not at:
        return lambda x: x
    _, _, _, body = block(at)
    kind, _, _, _, count = struct.unpack_from("<BBHHH", data, body)
    vals = struct.unpack_from("<%dd" % count, data, body + 24)
    if kind == 1:
        return lambda x: vals[0] + vals[1] * x
    if kind == 5:
        table = dict(zip(vals[0::2], vals[1::2]))
        return lambda x: table[x]
    raise SystemExit("conversion type %d" % kind)


def channels(at, out):
    while at:
        _, _, links, body = block(at)
        ctype, _, dtype, bit, byte, bits = struct.unpack_from("<BBBBII", data, body)
        out[text(links[2])] = dict(ctype=ctype, dtype=dtype, bit=bit, byte=byte, bits=bits,
                                   cc=conversion(links[4]), data=links[5])
        channels(links[1], out)
        at = links[0]


ident = data[:8]
unfinished = ident == b"UnFinMF "
_, _, hd_links, hd_body = block(64)
start_ns = struct.unpack_from("<Q", data, hd_body)[0]
dg = hd_links[0]
lines = []
while dg:
    _, _, dg_links, dg_body = block(dg)
    id_size = data[dg_body]
    assert id_size in (0, 1), "record ids of 0 or 1 byte"
    groups = {}
    cg = dg_links[1]
    while cg:
        _, _, cg_links, cg_body = block(cg)
        rid, _, flags, _, _, size, inval = struct.unpack_from("<QQHHIII", data, cg_body)
        chans = {}
        channels(cg_links[1], chans)
        groups[rid] = dict(at=cg, flags=flags, size=size + inval, chans=chans, rows=[], vlsd=[], vlsd_at={})
        cg = cg_links[0]
    if not dg_links[2]:
        dg = dg_links[0]
        continue
    ident, length, _, body = block(dg_links[2])
    assert ident == b"##DT"
    end = len(data) if unfinished else dg_links[2] + length
    pos = body
    while pos < end:
        if id_size:
            g = groups[data[pos]]
            pos += 1
        else:
            assert len(groups) == 1
            g = next(iter(groups.values()))
        if g["flags"] & 1:  # VLSD group: length, bytes
            n = struct.unpack_from("<I", data, pos)[0]
            g["vlsd_at"][sum(4 + len(v) for v in g["vlsd"])] = len(g["vlsd"])
            g["vlsd"].append(data[pos + 4:pos + 4 + n])
            pos += 4 + n
        else:
            g["rows"].append((pos, data[pos:pos + g["size"]]))
            pos += g["size"]
    by_at = {g["at"]: g for g in groups.values()}
    for g in groups.values():
        names = g["chans"]
        kind = next((k for k in ("CAN_DataFrame", "CAN_RemoteFrame", "CAN_ErrorFrame") if k in names), None)
        if kind is None:
            continue

        def column(leaf, default=None):
            c = names.get(kind + "." + leaf)
            if c is None:
                return [default] * len(g["rows"])
            if c["ctype"] in (3, 6):
                return [c["cc"](i) for i in range(len(g["rows"]))]
            values = []
            for _, row in g["rows"]:
                raw = int.from_bytes(row[c["byte"]:c["byte"] + (c["bit"] + c["bits"] + 7) // 8], "little")
                raw = (raw >> c["bit"]) & ((1 << c["bits"]) - 1)
                values.append(c["cc"](raw) if c["dtype"] != 10 else None)
            return values

        ts = names["Timestamp"]
        times = []
        for _, row in g["rows"]:
            raw = row[ts["byte"]:ts["byte"] + ts["bits"] // 8]
            x = struct.unpack("<d", raw)[0] if ts["dtype"] == 4 else int.from_bytes(raw, "little")
            times.append(ts["cc"](x))
        ids, ides, buses = column("ID", 0), column("IDE", 0), column("BusChannel", 1)
        edls, lengths, dlcs = column("EDL", 0), column("DataLength"), column("DLC")
        db = names.get(kind + ".DataBytes")
        for i, (at, row) in enumerate(g["rows"]):
            fd = int(edls[i])
            length = lengths[i] if lengths[i] is not None else dlcs[i]
            length = int(length) if fd else min(int(length), 8)
            payload = b""
            if kind == "CAN_DataFrame":
                if db["ctype"] == 1:
                    off = int.from_bytes(row[db["byte"]:db["byte"] + db["bits"] // 8], "little")
                    if db["data"] in by_at:  # a VLSD channel group
                        v = by_at[db["data"]]
                        payload = v["vlsd"][v["vlsd_at"][off]][:length]
                    else:  # an SD block: length, bytes, ...
                        ident, _, _, sd = block(db["data"])
                        assert ident == b"##SD"
                        n = struct.unpack_from("<I", data, sd + off)[0]
                        payload = data[sd + off + 4:sd + off + 4 + n][:length]
                else:
                    payload = row[db["byte"]:db["byte"] + length]
            us = start_ns // 1000 + round(times[i] * 1e6)
            lines.append((us, at, "%d.%06d %d %X %d %d %d %d %d %s" % (
                us // 10**6, us % 10**6, int(buses[i]), int(ids[i]), int(ides[i]), kind == "CAN_RemoteFrame",
                kind == "CAN_ErrorFrame", fd, 0 if kind == "CAN_ErrorFrame" else length, payload.hex().upper())))
    dg = dg_links[0]
for _, _, line in sorted(lines):
    print(line)
