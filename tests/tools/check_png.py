#!/usr/bin/env python3
"""Independent PNG checker for qrm's tests and figures (Python 3 standard library only).

Decodes a PNG without using any qrm code: walks the chunks and verifies every CRC-32
(binascii.crc32), checks IHDR, concatenates the IDAT chunks, inflates them with zlib (which also
verifies the Adler-32), and undoes the row filters (all five PNG filter types, so it works on
any 8-bit non-interlaced PNG, not only qrm's). Then, depending on the options:

  check_png.py FILE.png                      validate the structure; print size, colour type,
                                             and whether the image is non-blank (not all pixels equal)
  check_png.py FILE.png --require-nonblank   ... and fail if every pixel is equal
  check_png.py FILE.png --expect-raw FILE.raw
                                             ... and compare the pixels with a raw dump:
                                             header line "QRMRAW <width> <height> <channels>\\n"
                                             followed by the pixel bytes, rows from the top
  check_png.py FILE.png --expect-stored [--min-blocks N]
                                             ... and check that the zlib stream is made of stored
                                             deflate blocks (LEN <= 65535, NLEN = ~LEN, BFINAL only
                                             on the last), at least N of them

Exit status 0 when every check passes, 1 otherwise (with the reason on stderr).
"""
import argparse
import binascii
import struct
import sys
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}  # colour type -> samples per pixel (8-bit depth only)
COLOUR_NAMES = {0: "grey", 2: "RGB", 4: "grey+alpha", 6: "RGBA"}


class PngError(Exception):
    pass


def read_chunks(data):
    if data[:8] != SIGNATURE:
        raise PngError("bad signature %r" % data[:8])
    pos = 8
    chunks = []
    while pos < len(data):
        if pos + 12 > len(data):
            raise PngError("truncated chunk header at byte %d" % pos)
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        ctype = data[pos + 4:pos + 8]
        if length > 0x7FFFFFFF:
            raise PngError("chunk %r length %d exceeds 2^31-1" % (ctype, length))
        end = pos + 8 + length
        if end + 4 > len(data):
            raise PngError("chunk %r at byte %d runs past the end of the file" % (ctype, pos))
        body = data[pos + 8:end]
        (crc,) = struct.unpack(">I", data[end:end + 4])
        actual = binascii.crc32(ctype + body) & 0xFFFFFFFF
        if crc != actual:
            raise PngError("chunk %r at byte %d: CRC %08X stored, %08X computed" % (ctype, pos, crc, actual))
        chunks.append((ctype, body))
        pos = end + 4
        if ctype == b"IEND":
            break
    if pos != len(data):
        raise PngError("%d bytes after IEND" % (len(data) - pos))
    if not chunks or chunks[0][0] != b"IHDR":
        raise PngError("the first chunk is not IHDR")
    if chunks[-1][0] != b"IEND" or chunks[-1][1]:
        raise PngError("the file does not end with an empty IEND chunk")
    return chunks


def parse_stored_blocks(z):
    """Checks a zlib stream of stored deflate blocks; returns (payload, block count)."""
    if len(z) < 6:
        raise PngError("zlib stream too short")
    cmf, flg = z[0], z[1]
    if cmf & 0x0F != 8 or ((cmf << 8) | flg) % 31 != 0 or flg & 0x20:
        raise PngError("bad zlib header %02X %02X" % (cmf, flg))
    pos, blocks, out = 2, 0, bytearray()
    while True:
        if pos >= len(z) - 4:
            raise PngError("zlib stream ends inside the deflate data (block %d)" % blocks)
        header = z[pos]
        bfinal, btype = header & 1, (header >> 1) & 3
        if btype != 0:
            raise PngError("block %d has BTYPE %d, not 0 (stored)" % (blocks, btype))
        if header >> 3:
            raise PngError("block %d: padding bits after the block header are not zero" % blocks)
        length, nlength = struct.unpack("<HH", z[pos + 1:pos + 5])
        if length ^ nlength != 0xFFFF:
            raise PngError("block %d: NLEN %04X is not the complement of LEN %04X" % (blocks, nlength, length))
        out += z[pos + 5:pos + 5 + length]
        pos += 5 + length
        blocks += 1
        if bfinal:
            break
    if pos != len(z) - 4:
        raise PngError("%d bytes between the final block and the Adler-32" % (len(z) - 4 - pos))
    (adler,) = struct.unpack(">I", z[-4:])
    if adler != zlib.adler32(bytes(out)) & 0xFFFFFFFF:
        raise PngError("Adler-32 mismatch in the stored stream")
    return bytes(out), blocks


def unfilter(raw, width, height, bpp):
    stride = width * bpp
    if len(raw) != height * (stride + 1):
        raise PngError("inflated data is %d bytes, expected %d" % (len(raw), height * (stride + 1)))
    pixels = bytearray()
    prev = bytearray(stride)
    for y in range(height):
        ftype = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ftype == 0:
            pass
        elif ftype == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 0xFF
        elif ftype == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 0xFF
        elif ftype == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 0xFF
        elif ftype == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 0xFF
        else:
            raise PngError("row %d has filter type %d" % (y, ftype))
        pixels += line
        prev = line
    return bytes(pixels)


def decode(path):
    with open(path, "rb") as f:
        data = f.read()
    chunks = read_chunks(data)
    ihdr = chunks[0][1]
    if len(ihdr) != 13:
        raise PngError("IHDR has %d bytes, not 13" % len(ihdr))
    width, height, depth, ctype, comp, filt, interlace = struct.unpack(">IIBBBBB", ihdr)
    if width == 0 or height == 0:
        raise PngError("zero size %dx%d" % (width, height))
    if depth != 8 or ctype not in CHANNELS:
        raise PngError("bit depth %d, colour type %d: only 8-bit grey/RGB/(alpha) is supported" % (depth, ctype))
    if comp != 0 or filt != 0 or interlace != 0:
        raise PngError("compression %d, filter method %d, interlace %d (expected 0, 0, 0)" % (comp, filt, interlace))
    idat_chunks = [body for t, body in chunks if t == b"IDAT"]
    if not idat_chunks:
        raise PngError("no IDAT chunk")
    kinds = [t for t, _ in chunks]
    first, last = kinds.index(b"IDAT"), len(kinds) - 1 - kinds[::-1].index(b"IDAT")
    if any(t != b"IDAT" for t in kinds[first:last + 1]):
        raise PngError("IDAT chunks are not consecutive")
    z = b"".join(idat_chunks)
    d = zlib.decompressobj()
    raw = d.decompress(z) + d.flush()
    if not d.eof:
        raise PngError("the zlib stream is incomplete")
    if d.unused_data:
        raise PngError("%d bytes after the end of the zlib stream" % len(d.unused_data))
    bpp = CHANNELS[ctype]
    pixels = unfilter(raw, width, height, bpp)
    return {"width": width, "height": height, "ctype": ctype, "channels": bpp, "pixels": pixels,
            "zlib": z, "raw": raw, "idat_chunks": len(idat_chunks)}


def read_raw(path):
    with open(path, "rb") as f:
        data = f.read()
    newline = data.find(b"\n")
    fields = data[:newline].split() if newline > 0 else []
    if len(fields) != 4 or fields[0] != b"QRMRAW":
        raise PngError("%s: not a QRMRAW dump" % path)
    w, h, c = (int(v) for v in fields[1:])
    body = data[newline + 1:]
    if len(body) != w * h * c:
        raise PngError("%s: %d pixel bytes for %dx%dx%d" % (path, len(body), w, h, c))
    return w, h, c, body


def main():
    ap = argparse.ArgumentParser(description="Decode and check a PNG with the Python standard library only.")
    ap.add_argument("png")
    ap.add_argument("--expect-raw", help="QRMRAW dump of the expected pixels")
    ap.add_argument("--require-nonblank", action="store_true", help="fail if every pixel is equal")
    ap.add_argument("--expect-stored", action="store_true", help="the zlib stream must be stored deflate blocks")
    ap.add_argument("--min-blocks", type=int, default=1, help="with --expect-stored: at least this many blocks")
    args = ap.parse_args()
    try:
        img = decode(args.png)
        w, h, c = img["width"], img["height"], img["channels"]
        px = img["pixels"]
        first = px[:c]
        nonblank = any(px[i:i + c] != first for i in range(c, len(px), c))
        notes = []
        if args.expect_stored:
            payload, blocks = parse_stored_blocks(img["zlib"])
            if payload != img["raw"]:
                raise PngError("stored blocks and zlib disagree on the content")
            if blocks < args.min_blocks:
                raise PngError("%d stored block(s), expected at least %d" % (blocks, args.min_blocks))
            notes.append("%d stored deflate block(s)" % blocks)
        if args.expect_raw:
            rw, rh, rc, body = read_raw(args.expect_raw)
            if (rw, rh, rc) != (w, h, c):
                raise PngError("size %dx%dx%d, expected %dx%dx%d" % (w, h, c, rw, rh, rc))
            if body != px:
                bad = next(i for i in range(len(px)) if px[i] != body[i])
                p = bad // c
                raise PngError("pixel (%d, %d) channel %d is %d, expected %d"
                               % (p % w, p // w, bad % c, px[bad], body[bad]))
            notes.append("pixels match %s" % args.expect_raw)
        if args.require_nonblank and not nonblank:
            raise PngError("the image is blank: every pixel is %s" % list(first))
    except (PngError, OSError, zlib.error, struct.error) as e:
        print("check_png: %s: FAILED: %s" % (args.png, e), file=sys.stderr)
        return 1
    print("check_png: %s: OK: %dx%d %s 8-bit, %d IDAT chunk(s), %s%s"
          % (args.png, w, h, COLOUR_NAMES[img["ctype"]], img["idat_chunks"],
             "non-blank" if nonblank else "blank (all pixels equal)",
             "".join("; " + n for n in notes)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
