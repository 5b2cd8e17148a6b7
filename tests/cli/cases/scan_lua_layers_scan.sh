# hovox.layers_scan (issue 30 item 3): a scan printed from Lua streams from its data as `hovox layers VOLUME`
# does, the same bytes (every layer and the manifest), for a materials table and a colour table (whose dE2000
# both report); with keep_largest it goes through the model as the CLI does, the same bytes again; the sandbox
# keeps the stack inside the output directory
/usr/bin/python3 tests/io/scan/make_phantom.py "$TMP/ph" --size 20,24,18 --spacing 4,4,6 --formats nii >/dev/null || exit 9
mkdir "$TMP/out"
printf 'HU,VeroClear,Agilus30,VeroWhite\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n' > "$TMP/out/bone.csv"
printf 'HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n' > "$TMP/out/col.csv"
$HOVOX layers "$TMP/ph/phantom.nii" --iso -480 --lut "$TMP/out/bone.csv" --dpi 100,100 --layer-height 2 -o "$TMP/c1" -q >/dev/null || exit 8
$HOVOX layers "$TMP/ph/phantom.nii" --range -480,500 --lut "$TMP/out/col.csv" --dpi 100,100 --layer-height 2 --intent relative -o "$TMP/c2" -q >/dev/null || exit 8
$HOVOX layers "$TMP/ph/phantom.nii" --iso -480 --keep-largest --lut "$TMP/out/bone.csv" --dpi 100,100 --layer-height 2 -o "$TMP/c3" -q >/dev/null || exit 8
cat >"$TMP/out/s.lua" <<'LUA'
local ph, out = arg[1], arg[2]
local a = hovox.layers_scan(ph, {iso = -480, lut = out .. "/bone.csv", dpi = {100, 100}, layer_height = 2, dir = out .. "/l1"})
print("materials", a.layers, a.object_pixels, string.format("%.6f", a.materials.VeroWhite.achieved))
local b = hovox.layers_scan(ph, {range = {-480, 500}, lut = out .. "/col.csv", dpi = {100, 100}, layer_height = 2,
                                 intent = "relative", dir = out .. "/l2"})
print("colour", b.layers, b.object_pixels, b.colour.printer_voxels, string.format("%.2f %.2f", b.colour.mean_de2000_target,
      b.colour.mean_de2000_achieved))
local c = hovox.layers_scan(ph, {iso = -480, keep_largest = true, lut = out .. "/bone.csv", dpi = {100, 100},
                                 layer_height = 2, dir = out .. "/l3"})
print("model", c.layers, c.object_pixels)
print(pcall(hovox.layers_scan, ph, {iso = -480, lut = out .. "/bone.csv", dir = "/tmp/elsewhere"}))
print(pcall(hovox.layers_scan, ph, {lut = out .. "/bone.csv", dir = out .. "/x"}))
print(pcall(hovox.layers_scan, ph, {iso = 1, dir = out .. "/x"}))
LUA
$HOVOX run --sandbox --output-dir "$TMP/out" "$TMP/out/s.lua" "$TMP/ph/phantom.nii" "$TMP/out"; echo "rc=$?"
for k in 1 2 3; do
    n=0; d=0
    for f in "$TMP/c$k"/*; do
        n=$((n + 1)); cmp -s "$f" "$TMP/out/l$k/$(basename "$f")" || { d=$((d + 1)); echo "differs: c$k/$(basename "$f")"; }
    done
    echo "stack $k: $n files, $d differ"
done
