#!/usr/bin/env python3
"""Writes fuzz/seeds/png/: tiny PNGs of every layout `compare` decodes (grey,
grey+alpha, RGB, RGBA, palette with tRNS, 1-16 bits, interlaced, with text), so
the PNG fuzz target starts from each branch of the reader at a few hundred bytes
an input. Run from anywhere; the files are committed."""

import struct
import zlib
from pathlib import Path

OUT = Path(__file__).resolve().parent / "png"


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(width, height, depth, colour, rows, interlace=0, extra=b""):
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, interlace)
    raw = b"".join(b"\0" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def main():
    OUT.mkdir(exist_ok=True)
    seeds = {
        "grey1.png": png(8, 2, 1, 0, [b"\xa5", b"\x5a"]),
        "grey8.png": png(3, 2, 8, 0, [b"\x00\x80\xff", b"\x10\x20\x30"]),
        "grey-alpha8.png": png(2, 2, 8, 4, [b"\x00\xff\x80\x80", b"\xff\x00\x10\x10"]),
        "rgb8.png": png(2, 2, 8, 2, [b"\xff\x00\x00\x00\xff\x00", b"\x00\x00\xff\xff\xff\xff"]),
        "rgba16.png": png(1, 2, 16, 6, [b"\xff\xff\x00\x00\x12\x34\x80\x00",
                                        b"\x00\x01\x00\x02\x00\x03\xff\xff"]),
        "palette.png": png(4, 1, 2, 3, [b"\x1b"],
                           extra=chunk(b"PLTE", b"\x00\x00\x00\xff\x00\x00\x00\xff\x00\x00\x00\xff") +
                           chunk(b"tRNS", b"\x00\x80")),
        "interlaced.png": png(3, 3, 8, 0, [b"\x01\x02\x03"] * 3, interlace=1),
        "text.png": png(1, 1, 8, 2, [b"\x10\x20\x30"],
                        extra=chunk(b"tEXt", b"bristle:batch-key\x000123456789abcdef")),
    }
    for name, data in seeds.items():
        (OUT / name).write_bytes(data)


if __name__ == "__main__":
    main()
