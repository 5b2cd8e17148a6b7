# smsg item 7: `BENCH_ONLY=colour make bench` deleted grade.vdb, occ.vdb, paint.vdb and the trays
# graded/colour/painted in build/bench/colour whoever had made them. The section now writes what
# it does not keep into a directory of its own (mktemp run.XXXXXX) and removes only that: its only
# rm, and every output of its trays and models, go there. (Run by hand with sentinel files in
# build/bench/colour, BENCH_COLOUR_LAYERS=400:401: all four kept, no run.* left.)
s=scripts/bench/98-colour.sh
grep -n 'rm ' "$s"
grep -c -- '-o "\$run/' "$s"
grep -n -- '-o "\$cw/' "$s"
