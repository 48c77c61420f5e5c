#!/usr/bin/env python3
"""How two PNG images of the same size differ: "N of M pixels differ, by at most K" (K in levels of
the larger channel difference). 8-bit grey, RGB or RGBA, not interlaced, as rigsim writes them.

    python3 bench/png_difference.py A.png B.png

Standard library only (zlib and the PNG filters by hand), for bench scripts on a machine without
Pillow. Exit 0 after printing, 1 on an image it cannot read or sizes that differ.
"""

import struct
import sys
import zlib

CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}  # PNG colour type -> channels


def read_png(path):
    """(width, height, channels, rows of bytes) of an 8-bit, non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    at, idat, header = 8, b"", None
    while at < len(data):
        length = struct.unpack(">I", data[at:at + 4])[0]
        kind, chunk = data[at + 4:at + 8], data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"IDAT":
            idat += chunk
        at += 12 + length
    if header is None:
        raise ValueError(f"{path}: no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in CHANNELS or interlace:
        raise ValueError(f"{path}: only 8-bit, non-interlaced grey, RGB or RGBA images are read")
    bpp = CHANNELS[colour]
    stride, raw, rows = width * bpp, zlib.decompress(idat), []
    previous, k = bytearray(width * bpp), 0
    for _ in range(height):
        kind, line = raw[k], bytearray(raw[k + 1:k + 1 + stride])
        k += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = previous[x]
            c = previous[x - bpp] if x >= bpp else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        previous = line
    return width, height, bpp, rows


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 1
    try:
        wa, ha, ca, a = read_png(sys.argv[1])
        wb, hb, cb, b = read_png(sys.argv[2])
    except (OSError, ValueError, zlib.error) as e:
        print(f"png_difference.py: {e}", file=sys.stderr)
        return 1
    if (wa, ha, ca) != (wb, hb, cb):
        print(f"png_difference.py: the images differ in size or channels ({wa}x{ha}x{ca} against {wb}x{hb}x{cb})",
              file=sys.stderr)
        return 1
    differing, largest = 0, 0
    for y in range(ha):
        for x in range(wa):
            d = max(abs(a[y][x * ca + c] - b[y][x * ca + c]) for c in range(ca))
            if d:
                differing += 1
                largest = max(largest, d)
    print(f"{differing} of {wa * ha} pixels differ, by at most {largest}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
