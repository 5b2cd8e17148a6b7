#!/bin/sh
# tests/io/vdb/corrupt_vdb.sh - damaged and hostile .vdb files: truncations at every 1/64 of
# a graded model, one-bit flips spread over it, and crafted files (a 4096^3 active tile, a grid
# of an unsupported type, a rotated transform, a tiny and a huge voxel, no grids, a future
# version, grid offsets outside the file or out of step with the grids). The model has grid
# offsets (what hovox writes: `render` skips grids by them), and the same cuts at every 1/16 and
# 40 flips go to a copy without (an OpenVDB stream, as hovox wrote models before issue 17).
# Every case must end in 5 s, under 1 GiB, with one line on stderr, no OpenVDB text on stdout
# and a documented exit code: 1-4 for truncations and crafted files, 0-4 for a bit flip (a flip
# in a value or padding leaves a readable file). Never a crash, never exit 70.
set -u
: "${HOVOX:?set HOVOX to the hovox binary}"
PY=${PYTHON:-/usr/bin/python3}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
model=tests/data/models/linear2.vdb
stream=tests/data/models/linear2_stream.vdb
pass=0
fail=0

check() { # check NAME FILE LOWEST_OK_EXIT
    name=$1 file=$2 lo=$3
    for cmd in probe render; do
        if [ $cmd = probe ]; then set -- "$HOVOX" probe "$file" 1,1,1
        else set -- "$HOVOX" render "$file" -o "$TMP/x.png" --size 8,8 -q; fi
        /usr/bin/time -f "%M" -o "$TMP/rss" timeout 5 "$@" >"$TMP/out" 2>"$TMP/err"
        rc=$?
        rss=$(tail -n 1 "$TMP/rss")
        lines=$(wc -l <"$TMP/err")
        ok=1
        [ "$rc" -ge "$lo" ] && [ "$rc" -le 4 ] || ok=0
        [ "${rss:-0}" -le 1048576 ] || ok=0
        [ "$lines" -le 1 ] || ok=0
        ! grep -q "WARN" "$TMP/out" || ok=0 # OpenVDB's logging must not reach stdout
        if [ $ok = 1 ]; then pass=$((pass + 1)); else
            fail=$((fail + 1))
            echo "--- $name ($cmd): exit $rc, ${rss} KiB, $lines lines of stderr"
            head -c 400 "$TMP/err"
        fi
    done
}

size=$(wc -c <"$model")
i=1
while [ $i -lt 64 ]; do
    n=$((size * i / 64))
    head -c "$n" "$model" >"$TMP/t.vdb"
    check "truncated at $n of $size bytes" "$TMP/t.vdb" 1
    i=$((i + 1))
done
check "truncated by 100 bytes" "$model" 0 # the full file first: it must load
head -c $((size - 100)) "$model" >"$TMP/t.vdb"
check "truncated by 100 bytes" "$TMP/t.vdb" 1
check "stream" "$stream" 0
size=$(wc -c <"$stream")
i=1
while [ $i -lt 16 ]; do
    n=$((size * i / 16))
    head -c "$n" "$stream" >"$TMP/t.vdb"
    check "stream truncated at $n of $size bytes" "$TMP/t.vdb" 1
    i=$((i + 1))
done

"$PY" - "$model" "$stream" "$TMP" <<'PYEOF'
import struct, sys
src, stream, out = sys.argv[1], sys.argv[2], sys.argv[3]
data = open(src, 'rb').read()
for k in range(120):
    pos = (k * 7919) % len(data)
    b = bytearray(data)
    b[pos] ^= 1 << (k % 8)
    open('%s/flip%03d.vdb' % (out, k), 'wb').write(bytes(b))
sdata = open(stream, 'rb').read()
for k in range(40):
    pos = (k * 7907 + 13) % len(sdata)
    b = bytearray(sdata)
    b[pos] ^= 1 << (k % 8)
    open('%s/sflip%03d.vdb' % (out, k), 'wb').write(bytes(b))
# grid offsets: the descriptor of "occupancy" (name, type, no parent) ends with grid, blocks
# and end position, int64 each
d = b'\x09\x00\x00\x00occupancy\x0f\x00\x00\x00Tree_bool_5_4_3\x00\x00\x00\x00'
at = data.index(d) + len(d)
grid, blocks, end = struct.unpack('<qqq', data[at:at + 24])
def patched(name, g, b, e):
    p = bytearray(data)
    p[at:at + 24] = struct.pack('<qqq', g, b, e)
    open('%s/%s.vdb' % (out, name), 'wb').write(bytes(p))
patched('offset_end_beyond_file', grid, blocks, len(data) + 4096)
patched('offset_end_before_grid', grid, blocks, grid - 8)
patched('offset_end_early', grid, blocks, end - 100)
patched('offset_grid_elsewhere', grid + 16, blocks, end)
patched('offset_negative', -1, blocks, -1)
PYEOF
for f in "$TMP"/flip*.vdb "$TMP"/sflip*.vdb; do check "bit flip $(basename "$f")" "$f" 0; done
for f in offset_end_beyond_file offset_end_before_grid offset_end_early offset_grid_elsewhere offset_negative; do
    check "$f" "$TMP/$f.vdb" 1
done

"$PY" - "$TMP" <<'PYEOF'
import sys
import pyopenvdb as vdb
out = sys.argv[1]
g = vdb.BoolGrid(); g.name = 'occupancy'
g.fill((0, 0, 0), (4095, 4095, 4095), True, True)
vdb.write(out + '/huge_tile.vdb', grids=[g])
v = vdb.Vec3SGrid(); v.name = 'occupancy'; v.fill((0, 0, 0), (7, 7, 7), (1, 2, 3), True)
vdb.write(out + '/vector_grid.vdb', grids=[v])
r = vdb.BoolGrid(); r.name = 'occupancy'; r.fill((0, 0, 0), (7, 7, 7), True, True)
r.transform = vdb.createLinearTransform([[0.7071, 0.7071, 0, 0], [-0.7071, 0.7071, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
vdb.write(out + '/rotated.vdb', grids=[r])
t = vdb.BoolGrid(); t.name = 'occupancy'; t.fill((0, 0, 0), (7, 7, 7), True, True)
t.transform = vdb.createLinearTransform(voxelSize=1e-4)
vdb.write(out + '/tiny_voxel.vdb', grids=[t])
f = vdb.FloatGrid(); f.name = 'material.a'; f.fill((-2**30 - 104, 0, 0), (-2**30 - 97, 7, 7), 1.0, True)
vdb.write(out + '/far_away.vdb', grids=[f])
vdb.write(out + '/no_grids.vdb', grids=[])
PYEOF
[ $? = 0 ] || { echo "corrupt .vdb corpus: the crafted files could not be made"; exit 1; }
for f in huge_tile vector_grid rotated far_away no_grids; do check "$f" "$TMP/$f.vdb" 1; done
check "tiny voxel" "$TMP/tiny_voxel.vdb" 0
# a header version newer than OpenVDB's: refused, not parsed on with a warning on stdout
"$PY" -c "import sys; d = bytearray(open(sys.argv[1], 'rb').read()); d[8:12] = (19936).to_bytes(4, 'little'); \
open(sys.argv[2], 'wb').write(d)" "$model" "$TMP/future.vdb"
check "future version" "$TMP/future.vdb" 1
printf 'not a vdb at all' >"$TMP/text.vdb"
check "text" "$TMP/text.vdb" 1
: >"$TMP/empty.vdb"
check "empty" "$TMP/empty.vdb" 1
# inputs the fuzzers found (tests/io/vdb/found/); kept out of the fuzz corpus because ASan's
# operator new aborts where the plain build's address limit makes it throw
for f in tests/io/vdb/found/*.vdb; do check "found: $(basename "$f")" "$f" 1; done

# failed loads give back what they took: every damaged file above loaded 10 times in one process
# (the fuzz target's replay driver) stays near one load's memory. OpenVDB's root node leaked a
# child subtree per failed load, 270 KB here (the 10 rounds took 421 MB), until the bridge's
# checked readTopology
replay=$(dirname "$HOVOX")/fuzz/fuzz_vdb
if [ -x "$replay" ]; then
    set --
    for r in 1 2 3 4 5 6 7 8 9 10; do set -- "$@" "$TMP"/*.vdb; done
    /usr/bin/time -f "%M" -o "$TMP/rss" "$replay" "$@" >/dev/null 2>&1
    rss=$(tail -n 1 "$TMP/rss")
    if [ "${rss:-0}" -le 153600 ]; then pass=$((pass + 1)); else
        fail=$((fail + 1))
        echo "--- repeated failed loads: ${rss} KiB after 10 rounds (limit 150 MiB): memory is not given back"
    fi
fi

echo "corrupt .vdb corpus: $pass passed, $fail failed"
[ $fail = 0 ]
