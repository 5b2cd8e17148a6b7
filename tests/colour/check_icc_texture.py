#!/usr/bin/python3
"""tests/colour/check_icc_texture.py - a texture's embedded ICC profile is its colours' space
(issue 29 item 4): a 10 mm cube textured (OBJ + MTL map_Kd) by a flat picture that embeds Adobe
RGB (1998) (Ghostscript's a98.icc), as PNG (iCCP) and as JPEG (APP2), is painted 1 mm deep
(`hovox voxelize --colour-depth`); `hovox probe` one voxel inside a face gives the six fractions of
Pillow ImageCms's transform of the picture's colour from that profile to the CMYK output profile
(the same intent, mixed by the rule of hovox/colour.h) within 0.01, and not those of the same
numbers read as sRGB (they differ by more than 0.05). Usage: check_icc_texture.py HOVOX TMPDIR"""
import io
import os
import subprocess
import sys

from PIL import Image, ImageCms

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_paint  # noqa: E402  (the mixing rule, the resins, the output profile)

A98 = "/usr/share/color/icc/ghostscript/a98.icc"
COLOUR = (120, 160, 200)


def fractions(rgb, profile):
    tr = ImageCms.buildTransform(profile, ImageCms.getOpenProfile(check_paint.ICC), "RGB", "CMYK",
                                 renderingIntent=0)
    out = ImageCms.applyTransform(Image.new("RGB", (1, 1), rgb), tr)
    return check_paint.mix(out.getpixel((0, 0)))


def write_cube(d, picture):
    with open(os.path.join(d, "t.mtl"), "w") as f:
        f.write("newmtl skin\nmap_Kd %s\n" % picture)
    with open(os.path.join(d, "t.obj"), "w") as f:
        f.write("mtllib t.mtl\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl skin\n")
        for k in range(8):
            f.write("v %g %g %g\n" % (10 * (k in (1, 2, 5, 6)), 10 * (k in (2, 3, 6, 7)), 10 * (k >= 4)))
        for *_, facet in check_paint.FACES:
            v = facet.split()[1:]
            f.write("f %s\n" % " ".join("%s/%d" % (x, i + 1) for i, x in enumerate(v)))


def main():
    hovox, tmp = sys.argv[1], sys.argv[2]
    icc = open(A98, "rb").read()
    worst, apart = 0.0, 1.0
    for name, kw in (("t.png", {}), ("t.jpg", {"quality": 100, "subsampling": 0})):
        Image.new("RGB", (8, 8), COLOUR).save(os.path.join(tmp, name), icc_profile=icc, **kw)
        rgb = Image.open(os.path.join(tmp, name)).convert("RGB").getpixel((4, 4))  # as decoded
        write_cube(tmp, name)
        model = os.path.join(tmp, name + ".vdb")
        subprocess.run([hovox, "voxelize", os.path.join(tmp, "t.obj"), "--voxel-size", "0.5", "--colour-depth", "1",
                        "-o", model, "-q"], check=True, capture_output=True)
        row = check_paint.probe(hovox, model, [[5, 5, 0.25]])[0]
        got = [row.get(r, 0) for r in check_paint.RESINS]
        want = fractions(rgb, ImageCms.ImageCmsProfile(io.BytesIO(icc)))
        as_srgb = fractions(rgb, ImageCms.createProfile("sRGB"))
        worst = max(worst, max(abs(a - b) for a, b in zip(got, want)))
        apart = min(apart, max(abs(a - b) for a, b in zip(got, as_srgb)))
        print("%s %s: %s (Pillow through a98.icc %s)" % (name, rgb, " ".join("%.3f" % v for v in got),
                                                        " ".join("%.3f" % v for v in want)))
    print("embedded profile: within %.4f of Pillow ImageCms (<= 0.01); %.3f from the colour read as sRGB (> 0.05)"
          % (worst, apart))
    if worst > 0.01 or apart <= 0.05:
        sys.exit(1)


if __name__ == "__main__":
    main()
