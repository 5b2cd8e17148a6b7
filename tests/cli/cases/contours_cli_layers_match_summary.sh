# The .cli header's $$LAYERS, its $$LAYER records and the summary count the same layers (issue 32
# item 19: the header counted a zero layer more than the summary), ASCII and binary.
cd "$TMP"
"$HOVOX" generate sphere radius=5 -o s.stl >/dev/null
"$HOVOX" contours s.stl --layer-height 0.5 -o s.cli
grep -a '^\$\$LAYERS/' s.cli
grep -ac '^\$\$LAYER/' s.cli
"$HOVOX" contours s.stl --layer-height 0.5 -o b.cli --binary
grep -a '^\$\$LAYERS/' b.cli
/usr/bin/python3 - <<'PY'
import struct
d = open("b.cli", "rb").read()
p = d.index(b"$$HEADEREND") + 11
layers = 0
while p < len(d):
    cmd, = struct.unpack_from("<H", d, p)
    p += 2
    if cmd == 127:
        p += 4
        layers += 1
    else:
        n = struct.unpack_from("<3i", d, p)[2]
        p += 12 + 8 * n
print(layers, "layer records")
PY
