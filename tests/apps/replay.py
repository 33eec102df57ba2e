#!/usr/bin/env python3
"""Writes a finished force export again as a tribometer's software would
while the test runs: its header at once, then its rows at SPEED times real
time, flushed in blocks of BLOCK_S seconds of the test, each block cut at a
byte inside a row (the rest follows with the next block), as vendor
exports flush their buffers. Logs, per block, the wall time it was flushed
and the test time of its last complete row (unix seconds, for the watch's
latency).

usage: replay.py SOURCE DEST LOG [--speed 20] [--block 0.05] [--kill-at S]
                 [--split S [--restart-clock]]
--kill-at: stop after S seconds of the test in the middle of a row (a
writer killed mid-row).
--split: a file per S seconds of the test, as software that starts a new
file per block does: DEST holds {} for the block's number (from 1), each
file starts with the header, a block is finished before the next is
created; --restart-clock: each block's clock starts again at 0.
"""
import argparse
import os
import sys
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("source")
    ap.add_argument("dest")
    ap.add_argument("log")
    ap.add_argument("--speed", type=float, default=20.0)
    ap.add_argument("--block", type=float, default=0.05)
    ap.add_argument("--kill-at", type=float, default=None)
    ap.add_argument("--split", type=float, default=None)
    ap.add_argument("--restart-clock", action="store_true")
    a = ap.parse_args()
    with open(a.source, "rb") as f:
        lines = f.read().split(b"\n")
    header = []
    while lines and not lines[0][:1].isdigit():
        header.append(lines.pop(0))
    lines = [l for l in lines if l]
    times = [float(l.split(b",")[0]) for l in lines]
    log = open(a.log, "w")
    block_no = 0

    def open_block():
        nonlocal block_no
        block_no += 1
        f = open(a.dest.format(block_no) if a.split else a.dest, "wb")
        f.write(b"\n".join(header) + b"\n")
        f.flush()
        return f

    if a.split and a.restart_clock:
        for k, l in enumerate(lines):
            first, rest = l.split(b",", 1)
            lines[k] = b"%.6f," % (times[k] - a.split * int(times[k] // a.split)) + rest
    out = open_block()
    start = time.time()
    carry = b""
    i = 0
    t_block = a.block
    while i < len(lines):
        if a.split and times[i] >= a.split * block_no:
            out.write(carry)  # the block finished, then the next begun
            out.close()
            carry = b""
            out = open_block()
        j = i
        while j < len(lines) and times[j] < t_block and not (
                a.split and times[j] >= a.split * block_no):
            j += 1
        text = carry + b"".join(l + b"\n" for l in lines[i:j])
        if a.kill_at is not None and t_block >= a.kill_at:
            out.write(text + lines[j][: len(lines[j]) // 2] if j < len(lines) else text)
            out.flush()
            log.write("killed %.6f\n" % time.time())
            return 0
        # Cut inside the block's last row: a row still being written.
        cut = max(0, len(text) - 7) if j < len(lines) else len(text)
        if a.split and j < len(lines) and times[j] >= a.split * block_no:
            cut = len(text)  # the file's last rows: whole
        wait = start + t_block / a.speed - time.time()
        if wait > 0:
            time.sleep(wait)
        out.write(text[:cut])
        out.flush()
        carry = text[cut:]
        last = times[j - 2] if cut < len(text) and j - 2 >= i else times[j - 1] if j > i else None
        if last is not None:
            log.write("%.6f %.6f\n" % (time.time(), last))
        i = j
        if j < len(lines) and times[j] >= t_block:
            t_block += a.block
    if carry:
        out.write(carry)
        out.flush()
    log.write("done %.6f\n" % time.time())
    return 0


if __name__ == "__main__":
    sys.exit(main())
