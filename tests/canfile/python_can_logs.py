#!/usr/bin/python3
"""CAN logs through python-can (Debian's python3-can), the independent implementation the tests
hold lptn's readers and writers to.

  python_can_logs.py convert IN OUT   read IN, write OUT; formats by extension (.log candump -L,
                                      .asc Vector ASC, .blf Vector BLF)
  python_can_logs.py dump IN          one line per frame: seconds since the first frame (6
                                      decimals), id (hex), extended, remote, error, fd, length, data;
                                      an error frame by its flag alone (ASC keeps no id)
"""
import sys

import can


def convert(src, dst):
    with can.LogReader(src) as reader, can.Logger(dst) as writer:
        for msg in reader:
            writer.on_message_received(msg)


def dump(src):
    first = None
    for msg in can.LogReader(src):
        if first is None:
            first = msg.timestamp
        if msg.is_error_frame:  # by its flag alone: ASC keeps no id
            print("%.6f 0 0 0 1 0 0 " % (msg.timestamp - first))
            continue
        length = 0 if msg.is_remote_frame else len(msg.data)
        print("%.6f %X %d %d %d %d %d %s" % (msg.timestamp - first, msg.arbitration_id, msg.is_extended_id,
                                            msg.is_remote_frame, msg.is_error_frame, msg.is_fd,
                                            msg.dlc if msg.is_remote_frame else length,
                                            bytes(msg.data[:length]).hex().upper()))


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "convert":
        convert(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 3 and sys.argv[1] == "dump":
        dump(sys.argv[2])
    else:
        sys.exit(__doc__)
