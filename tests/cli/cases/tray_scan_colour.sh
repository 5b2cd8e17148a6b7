# issue 29 item 3 (and issue 30's limit): a scan printed from a colour lookup table as a tray part goes
# through the tray's colour map (--icc, --intent, --resins reach it; it used the default map), and the
# tray gives it the dE2000 `layers SCAN` gives the stack: in the part's manifest entry ("colour",
# printer voxels) and a colour line per coloured part in the summary. The phantom through a colour
# table with --intent relative: the tray's figures equal the layers stack's placed at the same spot
# (5,517,642 printer voxels, mean dE2000 4.41 target, 4.40 achieved); the tray's --icc (Ghostscript's
# ps_cmyk.icc) prints other fractions and --resins other names; two copies share the source, so its
# figures are theirs together.
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii >/dev/null || exit 9
cd "$TMP" || exit 1
printf 'HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n' > col.csv
"$HOVOX" layers ph/phantom.nii --iso -480 --lut col.csv --intent relative --profile j750 --place 60,60 \
    --layers 2000:2004 -o lay | grep '^colour'
"$HOVOX" tray -o tr --part ph/phantom.nii@60,60 --iso -480 --lut col.csv --intent relative --layers 2000:2004 \
    | grep -v '^memory'
echo "rc=$?"
"$HOVOX" tray -o tr_ps --part ph/phantom.nii@60,60 --iso -480 --lut col.csv --layers 2000:2004 \
    --icc /usr/share/color/icc/ghostscript/ps_cmyk.icc --resins C1,M1,Y1,K1,W1,Clear1 --resin C1=VeroCyan-V \
    --resin M1=VeroMagenta-V --resin Y1=VeroYellow-V --resin K1=VeroBlackPlus --resin W1=VeroPureWhite \
    --resin Clear1=VeroClear | grep '^colour'
"$HOVOX" tray -o tr2 --part ph/phantom.nii@60,60x2 --iso -480 --lut col.csv --intent relative --layers 2000:2004 \
    | grep '^colour'
/usr/bin/python3 - <<'PY'
import json
lay = json.load(open("lay/manifest.json"))
tray = json.load(open("tr/manifest.json"))["parts"][0]
a, b = lay["colour"], tray["colour"]
same = all(a[k] == b[k] for k in ("printer_voxels", "intent", "description", "icc")) and \
    all(abs(a[k] - b[k]) < 1e-9 for k in ("mean_de2000_target", "max_de2000_target", "mean_de2000_achieved"))
print("tray part colour = layers colour:", same)
targets = {m["name"]: m["target"] for m in lay["materials"]}
print("tray targets = layers targets:", all(abs(tray["materials"][n]["target"] - t) < 1e-9 for n, t in targets.items()))
d = json.load(open("tr_ps/manifest.json"))["parts"][0]
print("--icc ps_cmyk.icc, --resins:", d["colour"]["description"], sorted(d["materials"]), "cyan %.3f vs %.3f" %
      (d["materials"]["C1"]["target"], tray["materials"]["VeroCyan-V"]["target"]))
PY
