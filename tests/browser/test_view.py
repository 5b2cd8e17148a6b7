#!/usr/bin/python3
"""tests/browser/test_view.py - hovox view's pages in a real browser (Debian's chromium, headless,
driven over the DevTools protocol by tests/browser/cdp.py). Small stacks, a tray and a model are
made with hovox; each page is opened from file:// with no network, layers are stepped with the
keys, and what the page draws is read back (screenshots of its canvases at scale 1) and compared
with the layer PNGs decoded by Pillow and with the model's voxels read by pyopenvdb, not by hovox.

Needs HOVOX (the binary). No chromium: skipped with a message, unless HOVOX_REQUIRE_BROWSER=1 or
CI is set (then it fails). HOVOX_VIEW_SHOTS=DIR keeps screenshots of every page there.
"""
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402

HOVOX = os.environ.get("HOVOX", "build/hovox")
SHOTS = os.environ.get("HOVOX_VIEW_SHOTS")
checks = 0


def check(cond, what):
    global checks
    if not cond:
        raise AssertionError(what)
    checks += 1


def hovox(cwd, *args):
    subprocess.run([HOVOX] + list(args) + ["-q"] if args[0] not in ("generate",) else [HOVOX] + list(args),
                   cwd=cwd, check=True, stdout=subprocess.DEVNULL)


def png_rgb(path):
    from PIL import Image
    im = Image.open(path)
    im.load()
    return im


def repeat_rows(im, k):
    """Each row k times (nearest sampling at a row aspect of k)."""
    from PIL import Image
    return im.convert("RGB").resize((im.width, im.height * k), Image.NEAREST)


def shot(page, name):
    if SHOTS:
        os.makedirs(SHOTS, exist_ok=True)
        with open(os.path.join(SHOTS, name + ".png"), "wb") as f:
            f.write(page.screenshot())


def canvas_shot(page, canvas_expr, w, h):
    """The top-left w x h pixels of a canvas, as drawn (RGB)."""
    from PIL import Image
    r = page.eval("(function(){var r=%s.getBoundingClientRect();return [r.left,r.top,r.width,r.height];})()" % canvas_expr)
    check(r[2] >= w and r[3] >= h, "canvas %s is %gx%g, smaller than %dx%d" % (canvas_expr, r[2], r[3], w, h))
    data = page.screenshot({"x": r[0], "y": r[1], "width": w, "height": h})
    return Image.open(io.BytesIO(data)).convert("RGB")


def same(a, b, what, tol=0):
    from PIL import ImageChops
    check(a.size == b.size, "%s: sizes %s and %s" % (what, a.size, b.size))
    diff = ImageChops.difference(a.convert("RGB"), b.convert("RGB"))
    worst = max(hi for lo, hi in diff.getextrema())
    if worst > tol:
        bbox = diff.point(lambda v: 255 if v > tol else 0).getbbox()
        raise AssertionError("%s: differs by up to %d (tolerance %d) in %s" % (what, worst, tol, bbox))
    global checks
    checks += 1


def open_page(b, path):
    page = b.new_page()
    page.navigate("file://" + os.path.abspath(path))
    page.wait_for("window.hovoxView && window.hovoxView.ready")
    return page


def no_network_no_errors(page, what):
    urls = [e["request"]["url"] for e in page.events("Network.requestWillBeSent")]
    bad = [u for u in urls if not (u.startswith("file:") or u.startswith("data:"))]
    check(not bad, "%s asked the network for %s" % (what, bad[:3]))
    exc = page.events("Runtime.exceptionThrown")
    check(not exc, "%s threw: %s" % (what, exc[:1]))
    errs = [e for e in page.events("Runtime.consoleAPICalled") if e.get("type") == "error"]
    check(not errs, "%s logged errors: %s" % (what, errs[:1]))
    check(page.eval("hovoxView.errors.length") == 0, "%s: %s" % (what, page.eval("hovoxView.errors")))


def wait_layer(page, li):
    page.wait_for("hovoxView.drawnLayer === %d && hovoxView.layer() === %d" % (li, li))


def layer_at_1to1(page, stack, li, aspect, what, scale=1):
    """The layer canvas at `scale` device pixels per column from its corner equals the PNG."""
    m = json.load(open(os.path.join(stack, "manifest.json")))
    ref = png_rgb(os.path.join(stack, m["layers"][li]["file"]))
    page.eval("hovoxView.layerZoom.set(%d, 0, 0)" % scale)
    got = canvas_shot(page, "hovoxView.layerCanvas", ref.width * scale, ref.height * aspect * scale)
    from PIL import Image
    want = ref.convert("RGB").resize((ref.width * scale, ref.height * aspect * scale), Image.NEAREST)
    same(got, want, "%s layer %d at %d:1" % (what, li, scale))


def side_reference(stack, m, cut, aspect):
    """A cut through the stack from the PNGs: rows are layers, the highest at the top."""
    from PIL import Image
    layers = [png_rgb(os.path.join(stack, L["file"])).convert("RGB") for L in m["layers"]]
    w = cut["to"] - cut["from"]
    out = Image.new("RGB", (w, len(layers)))
    for k, im in enumerate(layers):
        y = len(layers) - 1 - k
        for t in range(w):
            p = (cut["from"] + t, cut["pos"]) if cut["axis"] == "row" else (cut["pos"], cut["from"] + t)
            out.putpixel((t, y), im.getpixel(p))
    return out.resize((w, len(layers) * aspect), Image.NEAREST)


def test_halftone(b, tmp):
    """A graded box at 100 x 50 dpi (a row is two columns tall, as on the J750), 0.508 mm layers."""
    hovox(tmp, "generate", "box", "max=12,8,3", "-o", "b.stl")
    hovox(tmp, "voxelize", "b.stl", "--voxel-size", "0.4", "-o", "o.vdb")
    hovox(tmp, "grade", "o.vdb", "-o", "g.vdb", "--materials", "soft,hard", "--colors", "#e04020,#2060e0",
          "--frf", "plane:0,0,0:1,0,0", "--ranges", "0,12,0", "--ms", "1,0", "--me", "0,1")
    hovox(tmp, "layers", "g.vdb", "--mesh", "b.stl", "-o", "ht", "--dpi", "100,50", "--layer-height", "0.508",
          "--background", "#ffffff")
    hovox(tmp, "view", "ht")
    stack = os.path.join(tmp, "ht")
    m = json.load(open(os.path.join(stack, "manifest.json")))
    n = len(m["layers"])
    page = open_page(b, os.path.join(stack, "index.html"))
    wait_layer(page, 0)
    shot(page, "halftone")
    page.eval("hovoxView.setOutlines(false)")
    layer_at_1to1(page, stack, 0, 2, "halftone")
    layer_at_1to1(page, stack, 0, 2, "halftone", scale=3)
    # keys step the layers
    page.eval("document.activeElement && document.activeElement.blur()")
    page.key("ArrowRight", key_code=39)
    page.key("ArrowRight", key_code=39)
    wait_layer(page, 2)
    layer_at_1to1(page, stack, 2, 2, "halftone")
    page.key("End", key_code=35)
    wait_layer(page, n - 1)
    layer_at_1to1(page, stack, n - 1, 2, "halftone")
    page.key("ArrowLeft", key_code=37)
    wait_layer(page, n - 2)
    page.key("Home", key_code=36)
    wait_layer(page, 0)
    page.key("PageUp", key_code=33)
    wait_layer(page, min(10, n - 1))
    # the slider and the layer box follow
    check(page.eval("document.querySelector('input[type=range]').value") == str(min(10, n - 1)), "slider")
    # side views: an x-z cut (a layer row of 0.508 mm over 0.254 mm columns: two to one) and a y-z cut
    D = page.eval("JSON.parse(document.getElementById('hovox-data').textContent)")
    rows = [c for c in D["cuts"] if c["axis"] == "row"]
    cols = [c for c in D["cuts"] if c["axis"] == "col"]
    check(len(rows) == m["height"] and len(cols) == min(32, m["width"]), "every row cut, 32 column cuts")
    check(D["cut_step"] == 1, "no subsampling")
    for axis, k, aspect in (("row", 9, 2), ("col", 20, 1)):
        ci = page.eval("hovoxView.setCut('%s', %d)" % (axis, k))
        page.wait_for("hovoxView.sideDrawn === %d" % ci)
        page.eval("hovoxView.sideZoom.set(1, 0, 0)")
        cut = D["cuts"][ci]
        want = side_reference(stack, m, cut, aspect)
        got = canvas_shot(page, "hovoxView.sideCanvas", want.width, want.height)
        same(got, want, "side view %s %d" % (axis, cut["pos"]))
    # the materials' target and achieved fractions are on the page
    text = page.eval("document.body.innerText")
    for mat in m["materials"]:
        check(mat["name"] in text, "material %s named" % mat["name"])
        check("%.4f" % mat["target"] in text, "target of %s shown" % mat["name"])
        check("%.4f" % mat["achieved"] in text, "achieved of %s shown" % mat["name"])
    no_network_no_errors(page, "halftone page")

    # a mask stack, written with the stack (--view)
    hovox(tmp, "layers", "--mesh", "b.stl", "-o", "mk", "--mode", "mask", "--dpi", "50,50", "--layer-height", "1",
          "--view")
    page = open_page(b, os.path.join(tmp, "mk", "index.html"))
    wait_layer(page, 0)
    page.eval("hovoxView.setOutlines(false)")
    layer_at_1to1(page, os.path.join(tmp, "mk"), 0, 1, "mask")
    no_network_no_errors(page, "mask page")
    return "halftone and mask stacks"


def test_fractions(b, tmp):
    """Fractions: grey layers per material, drawn as sum p_j colour_j."""
    from PIL import Image
    hovox(tmp, "layers", "g.vdb", "--mesh", "b.stl", "-o", "fr", "--mode", "fractions", "--dpi", "100,100",
          "--layer-height", "0.5")
    out = os.path.join(tmp, "pages", "fractions.html")  # the page elsewhere: layers by relative path
    os.makedirs(os.path.dirname(out))
    hovox(tmp, "view", "fr", "-o", out)
    stack = os.path.join(tmp, "fr")
    m = json.load(open(os.path.join(stack, "manifest.json")))
    page = open_page(b, out)
    check(page.eval("JSON.parse(document.getElementById('hovox-data').textContent).base") == "../fr/", "base")
    wait_layer(page, 0)
    page.eval("hovoxView.setOutlines(false)")
    li = len(m["layers"]) // 2
    page.eval("hovoxView.setLayer(%d)" % li)
    wait_layer(page, li)
    page.eval("hovoxView.layerZoom.set(1, 0, 0)")
    got = canvas_shot(page, "hovoxView.layerCanvas", m["width"], m["height"])
    greys = [png_rgb(os.path.join(stack, m["layers"][li]["files"][mat["name"]])).convert("L") for mat in m["materials"]]
    cols = [tuple(int(mat["color"][1 + 2 * k:3 + 2 * k], 16) for k in range(3)) for mat in m["materials"]]
    want = Image.new("RGB", (m["width"], m["height"]))
    for y in range(m["height"]):
        for x in range(m["width"]):
            want.putpixel((x, y), tuple(min(255, round(sum(g.getpixel((x, y)) * c[k] / 255 for g, c in zip(greys, cols))))
                                        for k in range(3)))
    same(got, want, "fractions layer %d (sum p_j colour_j)" % li, tol=3)
    shot(page, "fractions")
    no_network_no_errors(page, "fractions page")
    return "fractions stack"


def test_tray(b, tmp):
    """A tray on the J750 plate: every part named with its fractions; a part's pixels at 1:1."""
    hovox(tmp, "generate", "box", "max=6,6,0.5", "-o", "p.stl")
    hovox(tmp, "tray", "-o", "tr", "--part", "g.vdb,b.stl@40,30", "--part", "g.vdb,b.stl@70,30,90",
          "--part", "p.stl:VeroPureWhitex2", "--arrange", "yes", "--resin", "soft=VeroCyan-V",
          "--resin", "hard=VeroMagenta-V", "--layers", "0:12")
    hovox(tmp, "view", "tr", "-o", "tray.html")
    stack = os.path.join(tmp, "tr")
    m = json.load(open(os.path.join(stack, "manifest.json")))
    page = open_page(b, os.path.join(tmp, "tray.html"))
    wait_layer(page, 0)
    shot(page, "tray")
    text = page.eval("document.body.innerText")
    for p in m["parts"]:
        check("%s #%d" % (p["name"], p["copy"]) in text, "part %s #%d named" % (p["name"], p["copy"]))
        for name, f in p["materials"].items():
            check(name in text, "material %s of %s named" % (name, p["name"]))
            for key in ("target", "achieved"):
                if key in f:
                    check("%.4f" % f[key] in text, "%s %s of %s shown" % (key, name, p["name"]))
    # a part's box at 1:1: each plate row two screen pixels tall
    from PIL import Image
    page.eval("hovoxView.setOutlines(false)")
    c0, r0, w, h = m["parts"][0]["image_px"]
    page.eval("hovoxView.layerZoom.set(1, %d, %d)" % (-c0, -2 * r0))
    got = canvas_shot(page, "hovoxView.layerCanvas", w, 2 * h)
    ref = png_rgb(os.path.join(stack, "layer-00000.png")).crop((c0, r0, c0 + w, r0 + h))
    same(got, ref.convert("RGB").resize((w, 2 * h), Image.NEAREST), "tray part 1 at 1:1")
    page.eval("hovoxView.setOutlines(true)")
    shot(page, "tray-part")
    no_network_no_errors(page, "tray page")
    return "tray"


def test_model(b, tmp):
    """A model's slices: sum p_j colour_j / sum p_j of the voxels pyopenvdb reads, 8-bit fractions."""
    import pyopenvdb as vdb
    from PIL import Image
    hovox(tmp, "view", "g.vdb", "--size", "240,180")
    page = open_page(b, os.path.join(tmp, "g.html"))
    shot(page, "model")
    D = page.eval("JSON.parse(document.getElementById('hovox-data').textContent)")
    grids, meta = vdb.readAll(os.path.join(tmp, "g.vdb"))
    table = json.loads(meta["hovox.materials.json"])["materials"]
    acc = {g.name: g.getConstAccessor() for g in grids}
    cols = [[round(255 * c) for c in mt["color"][:3]] for mt in table]
    check([mt["name"] for mt in D["materials"]] == [mt["name"] for mt in table], "materials")
    check(len(D["renders"]) == 4, "four renders")
    # the first voxel of the page's box, by OpenVDB's transform
    lo = [round(v) for v in grids[0].transform.worldToIndex(tuple(D["origin_mm"]))]
    page.eval("hovoxView.setOutlines(false)")
    for a, U, V in ((2, 0, 1), (1, 0, 2), (0, 1, 2)):
        A = D["axes"][a]
        idx = len(A["slices"]) // 3
        page.eval("hovoxView.setSlice(%d, %d)" % (a, idx))
        page.wait_for("hovoxView.panels[%d].drawn === %d" % (a, idx))
        page.eval("hovoxView.panels[%d].zoom.set(1, 0, 0)" % a)
        got = canvas_shot(page, "hovoxView.panels[%d].zoom.canvas" % a, A["w"], A["h"])
        bad = 0
        for y in range(A["h"]):
            for x in range(A["w"]):
                ijk = [0, 0, 0]
                ijk[a] = lo[a] + A["slices"][idx]
                ijk[U] = lo[U] + x
                ijk[V] = lo[V] + A["h"] - 1 - y
                ijk = tuple(ijk)
                occ, active = acc["occupancy"].probeValue(ijk)
                if not (occ and active):
                    continue
                p = [round(255 * min(1, max(0, acc["material." + mt["name"]].getValue(ijk)))) / 255 for mt in table]
                s = sum(p)
                want = tuple(round(sum(pj * c[k] for pj, c in zip(p, cols)) / s) if s > 0 else 178 for k in range(3))
                have = got.getpixel((x, y))
                if max(abs(u - v) for u, v in zip(have, want)) > 1:
                    if bad < 5:
                        print("model slice %s: voxel %s at (%d, %d): fractions %s, page %s, expected %s"
                              % ("xyz"[a], ijk, x, y, p, have, want))
                    bad += 1
        check(bad == 0, "model slice %s: %d voxels differ" % ("xyz"[a], bad))
    no_network_no_errors(page, "model page")
    return "model"


def main():
    chromium = cdp.find_chromium()
    required = os.environ.get("HOVOX_REQUIRE_BROWSER") == "1" or os.environ.get("CI") not in (None, "", "0")
    try:
        import PIL  # noqa: F401
        missing = None if chromium else "chromium"
    except ImportError:
        missing = "Pillow (python3-pil)"
    if missing:
        if required:
            print("browser: FAILED: no %s, and HOVOX_REQUIRE_BROWSER=1 or CI is set "
                  "(scripts/install-deps.sh browser installs it)" % missing)
            return 1
        print("browser: skipped: no %s installed (scripts/install-deps.sh browser installs it; CI runs these tests)"
              % missing)
        return 0
    tmp = tempfile.mkdtemp(prefix="hovox-view-")
    b = cdp.Browser(chromium)
    done, failed = [], 0
    try:
        for t in (test_halftone, test_fractions, test_tray, test_model):
            try:
                done.append(t(b, tmp))
            except Exception:
                failed += 1
                print("--- browser: %s failed:" % t.__name__)
                traceback.print_exc()
    finally:
        b.close()
        shutil.rmtree(tmp, ignore_errors=True)
    print("browser: %d checks in %d pages (%s), %d failed" % (checks, len(done), ", ".join(done), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
