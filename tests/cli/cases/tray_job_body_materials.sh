# issue 27 item 1: a tray part's bodies get their materials from the job file ("materials":
# {"BODY": "MATERIAL"}) or the command line (--materials BODY=MATERIAL after the --part), the one
# rule of `layers --material BODY=MATERIAL` (whatever the file says). core_in_shell.3mf (a VeroWhite
# shell, an Agilus30 core) printed cyan and black: the job file and the command line give the same
# layer bytes; a mesh naming no materials (an OBJ group) prints once its body has one.
m=$SHARED/good/core_in_shell.3mf
cp "$m" "$TMP/cis.3mf"
cat >"$TMP/job.json" <<'JOB'
{"schema": 1, "layers": "185:186",
 "parts": [{"mesh": "cis.3mf", "at": [40, 40],
            "materials": {"shell": "VeroCyan-V", "core": "Agilus30Black"}}]}
JOB
$HOVOX tray "$TMP/job.json" -o "$TMP/a" | grep -v '^memory'
echo "rc=$?"
# the same part from the command line, OPTION BODY=MATERIAL after the --part: the job file's layer
same_layer() { # DIR OPTION LABEL
    $HOVOX tray -o "$TMP/$1" --part "$TMP/cis.3mf@40,40" "$2" shell=VeroCyan-V "$2" core=Agilus30Black \
        --layers 185:186 -q
    echo "rc=$?"
    cmp "$TMP/a/layer-00185.png" "$TMP/$1/layer-00185.png" && echo "$3: the same layer"
}
same_layer b --materials "job file and --materials"
# --material, as layers and voxelize spell it, is the same option (the help names both)
same_layer b2 --material "--material"
$HOVOX tray --help | grep -A1 -- '--materials\? BODY'
/usr/bin/python3 - "$TMP/a/manifest.json" <<'PY'
import json, sys
for p in json.load(open(sys.argv[1]))["parts"]:
    for k, v in p["materials"].items():
        print(p["name"], k, v["resin"], "%.2f" % v["achieved"])
PY
printf 'v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\no tip\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$TMP/tet.obj"
printf '{"mode": "mask", "parts": [{"mesh": "tet.obj", "at": [40, 40], "materials": {"tip": "VeroCyan-V"}}]}\n' >"$TMP/tet.json"
$HOVOX tray "$TMP/tet.json" -o "$TMP/c" | grep '^parts'
echo "rc=$?"
# refused, naming file, line and column: a material that is not a string, an empty body name, a
# body the mesh does not have (at its entry: an object's key, a list's element), "materials" beside
# "material" or a model; and
# --materials before any --part (exit 1 or 2, nothing written)
refused() { # NAME JSON (\n: a new line): the job file NAME.json, refused
    printf '%b\n' "$2" >"$TMP/$1.json"
    $HOVOX tray "$TMP/$1.json" -o "$TMP/d"; echo "rc=$?"
}
refused bad1 '{"parts": [{"mesh": "tet.obj",\n  "materials": {"tip": 3}}]}'
refused bad2 '{"parts": [{"mesh": "tet.obj", "materials": {"": "VeroCyan-V"}}]}'
refused bad3 '{"parts": [{"mesh": "tet.obj", "materials": {"tap": "VeroCyan-V"}}]}'
refused bad6 '{"parts": [{"mesh": "tet.obj",\n  "materials": ["tip=VeroCyan-V",\n    "tap=VeroCyan-V"]}]}'
refused bad4 '{"parts": [{"mesh": "tet.obj", "material": "VeroCyan-V", "materials": ["tip=VeroCyan-V"]}]}'
refused bad5 '{"parts": [{"model": "m.vdb", "mesh": "tet.obj", "materials": {"tip": "VeroCyan-V"}}]}'
$HOVOX tray --materials tip=VeroCyan-V --part "$TMP/tet.obj@40,40" -o "$TMP/d"; echo "rc=$?"
ls "$TMP"
