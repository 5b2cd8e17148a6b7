# The dry run's PNG estimate against the stack written (issue 26 item 3: the one encoder sends
# sparse layers to its span coder, dense ones to libdeflate; the estimate follows it layer by
# layer and was 2.3 to 10 times high before). A sparse tray (graded boxes, plain pins) in
# halftone and mask mode, and a dense one (a graded plate across the J750 plate, 120 mm deep: over
# a quarter of its bytes): within 25%.
cd "$TMP"
"$HOVOX" generate box max=12,8,1 -o g.stl >/dev/null
"$HOVOX" voxelize g.stl --voxel-size 0.4 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,12,0 --ms 1,0 --me 0,1 -q
"$HOVOX" generate box max=6,6,0.5 -o p.stl >/dev/null
"$HOVOX" generate box max=480,120,0.3 -o w.stl >/dev/null
"$HOVOX" voxelize w.stl --voxel-size 0.4 -o wo.vdb -q >/dev/null
"$HOVOX" grade wo.vdb -o w.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,480,0 --ms 1,0 --me 0,1 -q
check() {
    name=$1
    shift
    est=$("$HOVOX" tray -o "$name" "$@" --dry-run | sed -n 's/^estimate.*about \([0-9.]*\) \([KMG]\)iB of PNG$/\1 \2/p')
    "$HOVOX" tray -o "$name" "$@" -q >/dev/null || echo "rc=$?"
    /usr/bin/python3 - "$name" "$est" <<'PY'
import glob, os, sys
v, unit = sys.argv[2].split()
est = float(v) * {"K": 2**10, "M": 2**20, "G": 2**30}[unit]
real = sum(os.path.getsize(f) for f in glob.glob(sys.argv[1] + "/layer-*.png"))
print("%s: estimate / stack %.2f, within 25%%: %s" % (sys.argv[1], est / real, "yes" if abs(est / real - 1) <= 0.25 else "NO"))
PY
}
parts="--part g.vdb,g.stl@40,30 --part g.vdb,g.stl@70,30,90 --part p.stl:VeroPureWhitex2 --arrange yes"
# shellcheck disable=SC2086
check sparse $parts --resin A=VeroCyan-V --resin B=VeroMagenta-V
# shellcheck disable=SC2086
check sparse_mask $parts --mode mask --resin A=VeroCyan-V --resin B=VeroMagenta-V
check dense --part w.vdb,w.stl@245,195 --resin A=VeroCyan-V --resin B=VeroMagenta-V
