#!/usr/bin/env python3
"""Writes a finished force export again as a tribometer's software would
while the test runs: its header at once, then its rows at SPEED times real
time, flushed in blocks of BLOCK_S seconds of the test, each block cut at a
byte inside a row (the rest follows with the next block), as vendor
exports flush their buffers. Logs, per block, the wall time it was flushed
and the test time of its last complete row (unix seconds, for the watch's
latency).

usage: replay.py SOURCE DEST LOG [--speed 20] [--block 0.05] [--kill-at S]
--kill-at: stop after S seconds of the test in the middle of a row (a
writer killed mid-row).
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
    a = ap.parse_args()
    with open(a.source, "rb") as f:
        lines = f.read().split(b"\n")
    header = []
    while lines and not lines[0][:1].isdigit():
        header.append(lines.pop(0))
    lines = [l for l in lines if l]
    times = [float(l.split(b",")[0]) for l in lines]
    out = open(a.dest, "wb")
    log = open(a.log, "w")
    out.write(b"\n".join(header) + b"\n")
    out.flush()
    start = time.time()
    carry = b""
    i = 0
    t_block = a.block
    while i < len(lines):
        j = i
        while j < len(lines) and times[j] < t_block:
            j += 1
        text = carry + b"".join(l + b"\n" for l in lines[i:j])
        if a.kill_at is not None and t_block >= a.kill_at:
            out.write(text + lines[j][: len(lines[j]) // 2] if j < len(lines) else text)
            out.flush()
            log.write("killed %.6f\n" % time.time())
            return 0
        # Cut inside the block's last row: a row still being written.
        cut = max(0, len(text) - 7) if j < len(lines) else len(text)
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
        t_block += a.block
    if carry:
        out.write(carry)
        out.flush()
    log.write("done %.6f\n" % time.time())
    return 0


if __name__ == "__main__":
    sys.exit(main())
