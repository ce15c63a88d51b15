#!/usr/bin/env python3
"""Writes the seed corpora and regression inputs of the image and JSON-scene fuzzers (issue #15).

tests/fuzz/corpus-image/: small valid images of every format pathview reads (seed_*), and the crafted files of the
issue (repro_*): Radiance RLE data that made stb_image loop forever, tiny files declaring 23170x23170 pixels,
an EXR attribute declaring 2 GB, truncated files. tests/fuzz/corpus-json/: valid scene files and the wrong-typed
or out-of-range keys of the issue. Deterministic: run it again and the files are the same. The JPEG and PSD seeds
come from ImageMagick (`convert`) when it is installed, and are kept as they are otherwise.
Usage: tests/fuzz/make_corpus.py [output folder, default: the folder of this script]
"""
import os
import shutil
import struct
import subprocess
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else HERE
IMG = os.path.join(OUT, "corpus-image")
JSN = os.path.join(OUT, "corpus-json")
os.makedirs(IMG, exist_ok=True)
os.makedirs(JSN, exist_ok=True)


def put(folder, name, data):
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def pixels(w, h, c):
    return bytes((x * 37 + y * 91 + k * 53) & 0xFF for y in range(h) for x in range(w) for k in range(c))


# ---------------------------------------------------------------- PNG
def png(w, h, rgba):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + rgba[y * w * 4:(y + 1) * w * 4] for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# ---------------------------------------------------------------- TGA, BMP, PNM
def tga(w, h, rgb, rle=False):
    head = struct.pack("<BBBHHBHHHHBB", 0, 0, 10 if rle else 2, 0, 0, 0, 0, 0, w, h, 24, 0x20)
    if not rle:
        return head + rgb
    body = b""
    for i in range(0, w * h, 2):  # a run of 2 of each first pixel: valid RLE packets
        body += bytes([0x81]) + rgb[3 * i:3 * i + 3]
    return head + body


def bmp(w, h, rgb):
    stride = (w * 3 + 3) & ~3
    rows = b"".join(rgb[y * w * 3:(y + 1) * w * 3] + b"\0" * (stride - w * 3) for y in range(h))
    return (b"BM" + struct.pack("<IHHI", 54 + len(rows), 0, 0, 54) +
            struct.pack("<IiiHHIIiiII", 40, w, h, 1, 24, 0, len(rows), 2835, 2835, 0, 0) + rows)


def ppm(w, h, rgb):
    return b"P6\n%d %d\n255\n" % (w, h) + rgb


def pgm(w, h, grey):
    return b"P5\n%d %d\n255\n" % (w, h) + grey


# ---------------------------------------------------------------- GIF (1x1, the classic minimal file)
GIF_1x1 = bytes.fromhex("47494638396101000100800000000000ffffff2c00000000010001000002024401003b")


def gif_declaring(w, h):
    g = bytearray(GIF_1x1)
    g[6:10] = struct.pack("<HH", w, h)       # logical screen
    g[19 + 5:19 + 9] = struct.pack("<HH", w, h)  # image descriptor (after the 6-byte colour table at 13)
    return bytes(g)


# ---------------------------------------------------------------- Radiance HDR
HDR_HEAD = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n"


def hdr_rle(w, h):
    out = HDR_HEAD + b"-Y %d +X %d\n" % (h, w)
    for y in range(h):
        out += bytes([2, 2, w >> 8, w & 0xFF])
        for k in range(4):
            out += bytes([128 + w, 128 if k == 3 else (40 * (k + 1) + y) & 0x7F])  # one run per channel
    return out


def hdr_flat(w, h):
    return HDR_HEAD + b"-Y %d +X %d\n" % (h, w) + bytes([100, 80, 60, 128]) * (w * h)


# ---------------------------------------------------------------- OpenEXR (uncompressed scanlines, FLOAT B,G,R)
def exr_attr(name, typ, data):
    return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(data)) + data


def exr(w, h, value=0.5, window=None):
    chans = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    x0, y0, x1, y1 = window or (0, 0, w - 1, h - 1)
    head = (struct.pack("<ii", 20000630, 2) + exr_attr("channels", "chlist", chans) +
            exr_attr("compression", "compression", b"\0") +
            exr_attr("dataWindow", "box2i", struct.pack("<iiii", x0, y0, x1, y1)) +
            exr_attr("displayWindow", "box2i", struct.pack("<iiii", x0, y0, x1, y1)) +
            exr_attr("lineOrder", "lineOrder", b"\0") + exr_attr("pixelAspectRatio", "float", struct.pack("<f", 1)) +
            exr_attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0)) +
            exr_attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
    line = struct.pack("<%df" % (3 * w), *([value] * (3 * w)))
    table_end = len(head) + 8 * h
    chunks, offsets = b"", []
    for y in range(h):
        offsets.append(table_end + len(chunks))
        chunks += struct.pack("<ii", y0 + y, len(line)) + line
    return head + b"".join(struct.pack("<Q", o) for o in offsets) + chunks


def main():
    w, h = 16, 8
    rgb, rgba = pixels(w, h, 3), pixels(w, h, 4)
    # Seeds: valid images.
    put(IMG, "seed.png", png(w, h, rgba))
    # seed.webp and seed_lossy.webp (4x4, lossless and lossy) were written by libwebp's encoder and are committed as
    # they are: the standard library has no WebP encoder.
    put(IMG, "seed.tga", tga(w, h, rgb))
    put(IMG, "seed_rle.tga", tga(w, h, rgb, rle=True))
    put(IMG, "seed.bmp", bmp(w, h, rgb))
    put(IMG, "seed.ppm", ppm(w, h, rgb))
    put(IMG, "seed.pgm", pgm(w, h, pixels(w, h, 1)))
    put(IMG, "seed.gif", GIF_1x1)
    put(IMG, "seed_rle.hdr", hdr_rle(w, h))
    put(IMG, "seed_flat.hdr", hdr_flat(4, 2))
    put(IMG, "seed.exr", exr(w, h))
    if shutil.which("convert"):
        for ext in ("jpg", "psd"):
            subprocess.run(["convert", "-size", "16x8", "gradient:red-blue", "+set", "date:create", "+set",
                            "date:modify", "-strip", os.path.join(IMG, "seed." + ext)], check=True)

    # The hangs: an RLE count byte of 0, and data ending inside a run (stb_image 2.27 loops forever).
    put(IMG, "repro_hdr_rle_count0.hdr", HDR_HEAD + b"-Y 2 +X 8\n" + bytes([2, 2, 0, 8, 0, 0, 0, 0]))
    put(IMG, "repro_hdr_rle_ends_in_run.hdr", HDR_HEAD + b"-Y 2 +X 8\n" + bytes([2, 2, 0, 8, 3, 1, 2]))
    # Tiny files declaring huge images (23170^2 = 536 megapixels; 11585^2 = 134 megapixels).
    big = 23170
    put(IMG, "repro_huge.tga", struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, big, big, 24, 0x20))
    put(IMG, "repro_huge.bmp", bmp(1, 1, b"\0\0\0")[:18] + struct.pack("<ii", big, big) + bmp(1, 1, b"\0\0\0")[26:])
    put(IMG, "repro_huge.ppm", b"P6\n%d %d\n255\n" % (big, big) + b"\0" * 8)
    put(IMG, "repro_huge.gif", gif_declaring(big, big))
    put(IMG, "repro_huge.psd", b"8BPS" + struct.pack(">H6xHIIHH", 1, 3, big, big, 8, 3) + struct.pack(">III", 0, 0, 0)
        + struct.pack(">H", 0) + b"\0" * 16)
    # 117 bytes of flat (non-RLE: the first byte is not 2) pixels; stb decodes the missing 134 million as zeros.
    h11585 = HDR_HEAD + b"-Y 11585 +X 11585\n"
    put(IMG, "repro_huge_11585.hdr", h11585 + bytes([100, 80, 60, 128]) * ((117 - len(h11585)) // 4))
    put(IMG, "repro_huge_window.exr", exr(1, 1, window=(0, 0, 16383, 16383))[:600])
    # An EXR whose 'comments' attribute declares 2 GB (OpenEXR allocated it before reading).
    attr = struct.pack("<ii", 20000630, 2) + b"comments\0string\0" + struct.pack("<i", 0x7FFFFFF0)
    put(IMG, "repro_exr_attr_2gb.exr", attr + b"A" * (589 - len(attr)))
    if os.path.exists(os.path.join(IMG, "seed.jpg")):
        j = bytearray(open(os.path.join(IMG, "seed.jpg"), "rb").read())
        sof = next(i for i in range(len(j) - 1) if j[i] == 0xFF and j[i + 1] in (0xC0, 0xC1, 0xC2))
        j[sof + 5:sof + 9] = struct.pack(">HH", big, big)
        put(IMG, "repro_huge.jpg", bytes(j))
    # Truncated files: 64x64 images cut in half (stb decodes the missing part as black).
    tw = th = 64
    trgb = pixels(tw, th, 3)
    for name, data in (("tga", tga(tw, th, trgb)), ("bmp", bmp(tw, th, trgb)), ("ppm", ppm(tw, th, trgb)),
                       ("hdr", hdr_flat(tw, th))):
        put(IMG, "repro_truncated." + name, data[:len(data) // 2])
    put(IMG, "repro_truncated_rle.hdr", hdr_rle(w, h)[:-5])
    if shutil.which("convert"):
        for ext, size in (("gif", "64x64"), ("psd", "32x32"), ("jpg", "64x64")):
            seed = os.path.join(IMG, "seed_%s.%s" % (size, ext))
            subprocess.run(["convert", "-size", size, "gradient:red-blue", "-swirl", "90", "+set", "date:create",
                            "+set", "date:modify", "-strip", seed], check=True)
            data = open(seed, "rb").read()
            put(IMG, "repro_truncated." + ext, data[:len(data) // 2])

    # JSON scene files (the fuzzer provides a.obj, lit.obj and sky.hdr next to them).
    seeds = {
        "seed_min.json": '{"obj": "a.obj"}',
        "seed_full.json": '{"obj": "lit.obj", "camera": {"eye": [0, 1, 4], "target": [0, 0, 0], "up": [0, 1, 0], '
                          '"fov": 40, "aperture": 0.01, "focus_distance": 4}, "background": [0.1, 0.1, 0.1], '
                          '"two_sided_emitters": true, "bookmarks": [{"name": "side", "eye": [4, 1, 0]}], '
                          '"materials": {"m": {"type": "glossy", "base_color": [0.5, 0.5, 0.5], '
                          '"specular": [0.04, 0.04, 0.04], "roughness": 0.3, "ior": 1.5, "emission": [0, 0, 0]}}}',
        "seed_env.json": '{"obj": "a.obj", "environment": {"map": "sky.hdr", "rotation": 90, "strength": 2}, '
                         '"sun": {"direction": [0, 1, 0], "irradiance": 3, "angular_radius": 0.5}}',
        "repro_two_sided_string.json": '{"obj": "a.obj", "two_sided_emitters": "yes"}',
        "repro_fov_string.json": '{"obj": "a.obj", "camera": {"fov": "wide"}}',
        "repro_aperture_negative.json": '{"obj": "a.obj", "camera": {"aperture": -5}}',
        "repro_strength_negative.json": '{"obj": "a.obj", "environment": {"strength": -1}}',
        "repro_radius_negative.json": '{"obj": "a.obj", "sun": {"angular_radius": -1}}',
        "repro_environment_number.json": '{"obj": "a.obj", "environment": 5}',
        "repro_sun_string.json": '{"obj": "a.obj", "sun": "up"}',
        "repro_material_number.json": '{"obj": "lit.obj", "materials": {"m": 3}}',
        "repro_bookmarks_object.json": '{"obj": "a.obj", "bookmarks": {"name": "x"}}',
        "repro_map_hang.json": '{"obj": "a.obj", "environment": {"map": "hang.hdr"}}',
    }
    for name, text in seeds.items():
        put(JSN, name, text + "\n")


if __name__ == "__main__":
    main()
