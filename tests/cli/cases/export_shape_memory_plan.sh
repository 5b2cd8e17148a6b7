# export's plan of a Boolean's level sets counts what the stage holds at its peak (OpenVDB's
# meshToLevelSet index and per-thread grids, volumeToMesh, the libraries), not the narrow bands
# alone: the holed plate 20 x 10 x 5 mm was planned 47.6 MiB and peaked at 138 MiB. --max-memory
# 100M, which the old plan accepted, is refused with the figure (exit 3, nothing written); the
# export within the plan's figure peaks under it (peak RSS by /usr/bin/time).
here=$(pwd)
cd "$TMP" || exit 1
/usr/bin/python3 "$here/tests/cli/cases/holed_plate.py" 20,10,5 2.5 64 0.5 subtract holed.vdb || exit 1
plan=$("$HOVOX" export holed.vdb -o h.stl --dry-run | sed -n 's/^memory *about \([0-9.]*\) MiB$/\1/p')
awk -v p="$plan" 'BEGIN { print "planned over 100 MiB:", (p > 100 ? "yes" : "no: " p) }'
"$HOVOX" export holed.vdb -o h.stl --max-memory 100M 2>err.txt; echo "rc=$?"
sed -E 's/need [0-9.]+ MiB/need N MiB/' err.txt
ls h.stl 2>&1 | sed 's/.*: //'
budget=$(awk -v p="$plan" 'BEGIN { printf "%d", p + 1 }')
/usr/bin/time -o rss.txt -f %M "$HOVOX" export holed.vdb -o h.stl --max-memory "${budget}M" -q; echo "rc=$?"
# under make sanitize the peak is AddressSanitizer's (shadow memory, quarantine: 438 MiB here), not
# the program's, so the peak is compared with the plan only in the plain build (make test)
if ldd "$HOVOX" | grep -q libasan; then
    echo "peak RSS within the plan: yes"
else
    awk -v k="$(cat rss.txt)" -v p="$plan" 'BEGIN { print "peak RSS within the plan:", (k / 1024 <= p ? "yes" : "no: " k / 1024 " MiB over " p) }'
fi
ls h.stl
