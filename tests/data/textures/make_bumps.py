#!/usr/bin/env python3
"""tests/data/textures/make_bumps.py -- writes bumps.png beside itself: the height map of the gallery's
fig-displace (instess --displace).  64x64, 8-bit grey: a 4x4 lattice of round bumps, texel (x, y) =
round(255 * max(0, 1 - (d / 0.42)^2)^2), d the distance of the texel's centre from the centre of its 16x16 cell in
cell units.  It tiles (wraps) seamlessly.  Python's standard library only; run it to make the file again."""
import math
import os
import struct
import zlib


def height(x, y):
    fx = (x + 0.5) / 16.0 % 1.0 - 0.5
    fy = (y + 0.5) / 16.0 % 1.0 - 0.5
    v = max(0.0, 1.0 - (fx * fx + fy * fy) / (0.42 * 0.42)) ** 2
    return int(round(255 * v))


def chunk(kind, data):
    return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)


def main():
    w = h = 64
    raw = b''.join(b'\x00' + bytes(height(x, y) for x in range(w)) for y in range(h))
    png = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 0, 0, 0, 0)) +
           chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'bumps.png'), 'wb') as f:
        f.write(png)


if __name__ == '__main__':
    main()
