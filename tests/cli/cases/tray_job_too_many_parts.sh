# issue 32 item 12: a job file of 20,000 parts is refused before any part is read, naming the
# file and the place (it took 18 s: parts were added in quadratic time, then counted); a job of
# 2,500 parts is planned at once. The timeout only catches a return of the quadratic rule.
$HOVOX generate box size=2,2,2 -o "$TMP/pin.stl" >/dev/null
for n in 20000 2500; do
    awk -v n=$n 'BEGIN { printf "{\"schema\": 1, \"parts\": ["; for (i = 0; i < n; ++i) printf "%s{\"mesh\": \"pin.stl\", \"material\": \"VeroPureWhite\", \"at\": [%d, %d]}", (i ? ", " : ""), 6 + (i % 60) * 8, 6 + int(i / 60) * 8; print "]}" }' >"$TMP/job$n.json"
    timeout 20 $HOVOX tray "$TMP/job$n.json" -o "$TMP/t" --dry-run >/dev/null
    echo "rc=$?"
done
