"""A small PNG reader (standard library only) for the preview tests: 8-bit greyscale, RGB, RGBA, grey+alpha,
non-interlaced, the five scanline filters. Independent of Blender, which wrote the files."""
import struct
import zlib

_CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}


def _paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def read_png(path):
    """Returns (width, height, channels, rows): rows[y] is a bytes-like of width * channels values, top row first."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG file" % path)
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in _CHANNELS or interlace:
        raise ValueError("%s: only 8-bit non-interlaced grey/RGB/RGBA PNGs are supported" % path)
    ch = _CHANNELS[colour]
    raw = zlib.decompress(b"".join(idat))
    stride = width * ch
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b = previous[i]
            c = previous[i - ch] if i >= ch else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                line[i] = (line[i] + _paeth(a, b, c)) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, ch, rows


def pixels(path):
    """(width, height, list of per-pixel tuples of the first three channels, or the grey value thrice)."""
    width, height, ch, rows = read_png(path)
    out = []
    for row in rows:
        for x in range(width):
            p = row[x * ch:(x + 1) * ch]
            out.append((p[0], p[1], p[2]) if ch >= 3 else (p[0], p[0], p[0]))
    return width, height, out
