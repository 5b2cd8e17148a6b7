# Every enum value has one spelling (issue 26 item 5): the name given on the command line is the
# one the summary prints and the manifest records, for each value of layers' mode, method,
# halftone and fill rule, tray's mode, render's mode and export's coarsen rule. (The halftone
# methods were 'bluenoise'/'error' as options but 'blue-noise'/'error-diffusion' in manifests
# and summaries.)
cd "$TMP"
"$HOVOX" generate box max=4,4,0.2 -o b.stl >/dev/null
"$HOVOX" voxelize b.stl --voxel-size 0.25 -o o.vdb -q >/dev/null
"$HOVOX" grade o.vdb -o g.vdb --materials A,B --frf plane:0,0,0:1,0,0 --ranges 0,4,0 --ms 1,0 --me 0,1 -q
manifest() { python3 -c 'import json,sys; d=json.load(open(sys.argv[1]))
print(" ".join("%s=%s" % (k, d[k]) for k in ("mode", "method", "halftone", "fill_rule") if k in d))' "$1"; }
n=0
layers() { # MODE METHOD HALFTONE RULE
    n=$((n + 1))
    extra=""
    [ "$1" = halftone ] && extra=" --halftone $3"
    [ "$1" = mask ] || extra="$extra --method $2"
    "$HOVOX" layers g.vdb --mesh b.stl -o "s$n" --dpi 100,100 --layer-height 0.1 --mode "$1" --fill-rule "$4" $extra \
        >out.txt || return
    said=$(sed -n 's/^wrote .*object pixels, \(.*\))$/\1/p' out.txt)
    recorded=$(manifest "s$n/manifest.json")
    want="mode=$1"
    [ "$1" = mask ] || want="$want method=$2"
    [ "$1" = halftone ] && want="$want halftone=$3"
    want="$want fill_rule=$4"
    how="$1"
    [ "$1" = halftone ] && how="halftone $3"
    [ "$said" = "$how" ] && [ "$recorded" = "$want" ] && ok=same || ok=DIFFERENT
    echo "layers --mode $1$extra --fill-rule $4: summary '$said', manifest '$recorded': $ok"
}
layers halftone resample bluenoise nonzero
layers halftone direct error evenodd
layers fractions resample - evenodd
layers fractions direct - nonzero
layers mask - - evenodd
for m in halftone mask; do
    "$HOVOX" tray -o "t_$m" --part b.stl:VeroCyan-V@40,40 --mode $m --layers 0:1 >out.txt || continue
    said=$(sed -n 's/^printer *j750, \(.*\)$/\1/p' out.txt)
    recorded=$(manifest "t_$m/manifest.json")
    [ "$said" = "$m" ] && [ "$recorded" = "mode=$m" ] && ok=same || ok=DIFFERENT
    echo "tray --mode $m: summary '$said', manifest '$recorded': $ok"
done
for m in volume surface; do
    said=$("$HOVOX" render g.vdb -o "r_$m.png" --size 16x16 --mode $m | sed -n 's/^image *16 x 16, \([a-z]*\),.*/\1/p')
    [ "$said" = "$m" ] && ok=same || ok=DIFFERENT
    echo "render --mode $m: summary '$said': $ok"
done
for k in majority any; do
    said=$("$HOVOX" export g.vdb -o "e_$k.vtu" --coarsen 2 --keep $k | sed -n 's/.*blocks, keep \([a-z]*\)).*/\1/p')
    [ "$said" = "$k" ] && ok=same || ok=DIFFERENT
    echo "export --keep $k: summary '$said': $ok"
done
