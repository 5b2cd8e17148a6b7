# issue 27 item 3: a Y-up OBJ turned Z-up (--up y, or --rotate x:90) gives the same J750 stack,
# layer for layer and byte for byte, as the same part exported Z-up; x:-90 or no turn does not.
cat >"$TMP/zup.obj" <<'OBJ'
# an L bracket exported Z-up: its profile in x,z extruded 20 mm along y
v 0 0 0
v 30 0 0
v 30 0 4
v 6 0 4
v 6 0 25
v 0 0 25
v 0 20 0
v 30 20 0
v 30 20 4
v 6 20 4
v 6 20 25
v 0 20 25
f 1 2 3
f 7 9 8
f 1 3 4
f 7 10 9
f 1 4 5
f 7 11 10
f 1 5 6
f 7 12 11
f 1 8 2
f 1 7 8
f 2 9 3
f 2 8 9
f 3 10 4
f 3 9 10
f 4 11 5
f 4 10 11
f 5 12 6
f 5 11 12
f 6 7 1
f 6 12 7
OBJ
# the Y-up export of the same part, written independently of hovox: (x, y, z) -> (x, z, -y)
awk '$1 == "v" { z = -$3; if (z == 0) z = 0; print "v", $2, $4, z; next } { print }' "$TMP/zup.obj" >"$TMP/yup.obj"
stack() { # NAME MESH [placement...]
    name=$1 mesh=$2
    shift 2
    $HOVOX layers --mesh "$TMP/$mesh" --mode mask --profile j750 -o "$TMP/$name" "$@" | grep -E "^(placed|image|layers)"
}
same() { # A B: every layer file the same bytes
    a=$(ls "$TMP/$1" | grep -c png) b=$(ls "$TMP/$2" | grep -c png) d=0
    for f in "$TMP/$1"/*.png; do cmp -s "$f" "$TMP/$2/$(basename "$f")" || d=$((d + 1)); done
    echo "$1 vs $2: $a and $b layers, $d differ"
}
stack zup zup.obj
stack up_y yup.obj --up y
stack rot_x90 yup.obj --rotate x:90
stack rot_xm90 yup.obj --rotate x:-90
stack raw yup.obj
same zup up_y
same zup rot_x90
same zup rot_xm90
