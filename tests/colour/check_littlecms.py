#!/usr/bin/python3
"""tests/colour/check_littlecms.py - the colour map against an independent LittleCMS caller (issue 29):
`hovox colour --json` on colours across the sRGB cube (and with alpha) against Pillow's ImageCms
(sRGB -> the same output profile, same intent), mixed by the rule of hovox/colour.h; every fraction
must agree within 0.01. Usage: check_littlecms.py HOVOX [--icc FILE] [--intent NAME]"""
import json
import subprocess
import sys

from PIL import Image, ImageCms

INTENTS = {"perceptual": 0, "relative": 1, "saturation": 2, "absolute": 3}


def mix(cmyk, alpha):
    ink = [v / 255.0 for v in cmyk]
    t = sum(ink)
    white = 1 - t if t < 1 else 0
    scale = 1 / t if t > 1 else 1
    return [alpha * v * scale for v in ink] + [alpha * white, 1 - alpha]


def profile_args(extra):
    """The profile and intent of --icc FILE and --intent NAME among extra (default: hovox's)."""
    icc = "/usr/share/color/icc/ghostscript/default_cmyk.icc"
    intent = "perceptual"
    for i, a in enumerate(extra):
        if a == "--icc":
            icc = extra[i + 1]
        if a == "--intent":
            intent = extra[i + 1]
    return icc, intent


def main():
    hovox = sys.argv[1]
    extra = sys.argv[2:]
    icc, intent = profile_args(extra)
    steps = [0, 51, 128, 204, 255]
    colours = [(r, g, b, 255) for r in steps for g in steps for b in steps]
    colours += [(255, 0, 0, 128), (10, 200, 30, 0), (90, 90, 250, 200)]
    args = ["#%02x%02x%02x%02x" % c for c in colours]
    out = subprocess.run([hovox, "colour", "--json"] + extra + args, check=True, capture_output=True, text=True)
    got = json.loads(out.stdout)
    srgb = ImageCms.createProfile("sRGB")
    prof = ImageCms.getOpenProfile(icc)
    tr = ImageCms.buildTransform(srgb, prof, "RGB", "CMYK", renderingIntent=INTENTS[intent])
    im = Image.new("RGB", (len(colours), 1))
    im.putdata([c[:3] for c in colours])
    out = Image.new("CMYK", im.size)
    # the transform's own apply: ImageCms.applyTransform also copies the output profile into the
    # image and fails on profiles Pillow cannot size (Ghostscript's ps_cmyk.icc)
    tr.transform.apply(im.im.id, out.im.id)
    cmyk = list(out.getdata())
    worst = 0.0
    for c, k, g in zip(colours, cmyk, got["colours"]):
        want = mix(k, c[3] / 255.0)
        have = g["fractions"]
        if abs(sum(have) - 1) > 1e-5:
            sys.exit("%s: fractions sum to %g" % (g["colour"], sum(have)))
        for w, h in zip(want, have):
            worst = max(worst, abs(w - h))
    if worst > 0.01:
        sys.exit("fractions differ from LittleCMS (Pillow) by %.4f > 0.01" % worst)
    print("%d colours, %s intent, %s: every fraction within 0.01 of Pillow ImageCms"
          % (len(colours), intent, got["description"]))


if __name__ == "__main__":
    main()
