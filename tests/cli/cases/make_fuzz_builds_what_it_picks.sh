# review item 4: `make fuzz FUZZ_ONLY=x` builds what harness x needs: build-fuzz/libhovox.a and
# no OpenVDB bridge (before, the instrumented bridge was built for every pick, though fuzz_vdb, the
# one harness that loads it, has its own build in build-fuzz-ub); FUZZ_ONLY=vdb builds
# build-fuzz-ub alone; a pick that names no harness is refused (exit 2) before anything is built.
# Dry runs (make -n -B: as if nothing were built yet) say what would be compiled, and write nothing.
yn() { if grep -q -- "$1" "$2"; then echo yes; else echo no; fi; }
touch "$TMP/mark"
for pick in tray_job vdb; do
    MAKEFLAGS= make --no-print-directory -n -B fuzz FUZZ_ONLY=$pick >"$TMP/$pick" 2>&1
    echo "FUZZ_ONLY=$pick: build-fuzz library $(yn ' -o build-fuzz/obj/' "$TMP/$pick")," \
        "build-fuzz-ub library $(yn ' -o build-fuzz-ub/obj/' "$TMP/$pick")," \
        "OpenVDB bridge $(yn 'vdb_bridge.cpp -o' "$TMP/$pick")," \
        "fuzz_tray_job $(yn 'for t in tests/fuzz/fuzz_tray_job.c;' "$TMP/$pick")," \
        "fuzz_vdb $(yn 'libfuzzer/fuzz_vdb -max' "$TMP/$pick")"
done
MAKEFLAGS= make --no-print-directory fuzz FUZZ_ONLY=nosuch 2>&1 | grep -v '^make\(\[[0-9]*\]\)\?: \*\*\*'
MAKEFLAGS= make --no-print-directory fuzz FUZZ_ONLY=nosuch >/dev/null 2>&1; echo "rc=$?"
echo "written by the dry runs: $(find build-fuzz build-fuzz-ub -newer "$TMP/mark" 2>/dev/null | wc -l) files"
