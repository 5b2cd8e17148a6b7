# README "hovox view": its example runs verbatim (the section's sh block, `hovox` being the binary
# under test); the example is printed first, so a change to it shows here too
readme=$(pwd)/README.md
cd "$TMP"
awk '/^### `hovox view /{s=1} s&&/^```sh/{f=1;next} f&&/^```/{exit} f' "$readme" >example.sh
cat example.sh
sed 's|^hovox |"$HOVOX" |' example.sh >run.sh
sh -e run.sh >out 2>err
echo "rc=$?"
# what each command wrote (the fractions the layers report depend on the build's floating point)
grep -E '^(wrote|page|stack|side views|layers from|slices|renders) ' out | sed 's/([0-9.]* [KM]iB)/(SIZE)/'
cat err
ls box_j750 | grep -v '^layer-'
ls *.html
grep -c 'id="hovox-data"' box_j750/index.html box_j750.html box_graded.html
