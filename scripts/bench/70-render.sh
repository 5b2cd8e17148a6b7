# scripts/bench/70-render.sh - issue 8: 1024x1024 ray-cast render of a 256-voxel graded model
# (Wu's gear: voxelized at 256, three materials by distance to the axis, bench_render_model)
# vs `vdb_render MODEL.vdb out.png -res 1024x1024 -step 1` on a "density" grid of the same
# voxels (occupancy as 0/1) in the same file. Goal: volume mode <= 1.0x vdb_render's wall time.
# Fairness: same grid, image size, step (1 voxel), camera (eye, target, up, 30 degree field of
# view) and thread count (all cores); both times include loading the model and writing the PNG.
# vdb_render integrates absorption + scattering with a shadow ray per sample (extinction 1.6
# per voxel at density 1); hovox shades with the occupancy gradient and a key light. hovox is
# timed at its default (translucent, 16 / extent: rays cross the whole part) and with the
# same extinction as vdb_render (1.6 per voxel), plus surface mode.
echo
echo "== render: 1024x1024, 256-voxel graded gear, vs vdb_render -res 1024x1024 -step 1 (goal: volume <= 1.0x)"
drv=$BUILD/bench-tools/bench_render_model
if [ ! -x "$drv" ] || ! command -v vdb_render >/dev/null 2>&1; then
    echo "skipped: needs $drv (make bench-tools) and vdb_render (libopenvdb-tools)"
else
    gear=$work/gear.stl
    [ -f "$gear" ] || "$HOVOX" generate gear -o "$gear" >/dev/null
    "$HOVOX" voxelize "$gear" --dims 256 -o "$work/gear256.vdb" -q >/dev/null
    model=$work/gear256_graded.vdb
    "$drv" "$work/gear256.vdb" "$model"
    # the generated gear: tip radius 39.45, height 39.45 from z = 0; iso view from 190 mm
    eye=$(awk 'BEGIN { d = 190 / sqrt(3); printf "%.4f,%.4f,%.4f", d, -d, 19.725 + d }')
    tgt=0,0,19.725
    voxel=$("$HOVOX" voxelize "$gear" --dims 256 --dry-run | awk '/^grid/ {print $9}')
    matched=$(awk -v v="$voxel" 'BEGIN { printf "%.4f", 1.6 / v }')
    cam="--eye $eye --target $tgt --up 0,0,1 --fov 30 --size 1024x1024"
    # shellcheck disable=SC2086
    t_vol=$(median render_volume "$HOVOX" render "$model" $cam --step 1 -o "$work/render_volume.png" -q)
    # shellcheck disable=SC2086
    t_mat=$(median render_volume_matched "$HOVOX" render "$model" $cam --step 1 --density "$matched" \
        -o "$work/render_volume_matched.png" -q)
    # shellcheck disable=SC2086
    t_srf=$(median render_surface "$HOVOX" render "$model" $cam --surface -o "$work/render_surface.png" -q)
    t_vdb=$(median render_vdb vdb_render "$model" "$work/render_vdb.png" -res 1024x1024 -step 1 \
        -name density -translate "$eye" -lookat "$tgt" -up 0,0,1 -fov 30)
    # shellcheck disable=SC2086
    m_vol=$(peak_rss "$HOVOX" render "$model" $cam --step 1 -o "$work/render_volume.png" -q)
    m_vdb=$(peak_rss vdb_render "$model" "$work/render_vdb.png" -res 1024x1024 -step 1 -name density \
        -translate "$eye" -lookat "$tgt" -up 0,0,1 -fov 30)
    printf "hovox render (volume, default density)      %7.3f s (%6.1f MiB)  ratio %sx\n" "$t_vol" "$m_vol" \
        "$(ratio "$t_vol" "$t_vdb")"
    printf "hovox render (volume, vdb_render extinction) %7.3f s            ratio %sx\n" "$t_mat" \
        "$(ratio "$t_mat" "$t_vdb")"
    printf "hovox render --surface                      %7.3f s            ratio %sx\n" "$t_srf" \
        "$(ratio "$t_srf" "$t_vdb")"
    printf "vdb_render -step 1 (density grid)           %7.3f s (%6.1f MiB)\n" "$t_vdb" "$m_vdb"
    echo "(images in $work/render_*.png)"
fi

# issue 17: Wu's shaft (hovox generate cylinder, --dims 256, graded from its contour) on one
# camera for both: hovox --eye 75,200,200 --target 75,0,0 --up 0,0,1 --fov 44.8 and vdb_render
# -translate 75,200,200 -lookat 75,0,0 -up 0,0,1 (44.8 degrees is its default 41.2 mm aperture
# at 50 mm), -step 1, on the occupancy as a fog volume ("density", in the same file), at 16^2
# (the fixed cost: load and scene set-up), 1024^2 and 2048^2. hovox and vdb_render runs
# alternate; medians of $runs. Goals: <= 0.7x at 1024^2 and 2048^2; fixed cost <= 50 ms.
echo
echo "== render: Wu's shaft at 256, same camera and size as vdb_render (goals: <= 0.7x at 1024^2 and 2048^2, 16^2 <= 50 ms)"
if [ ! -x "$drv" ] || ! command -v vdb_render >/dev/null 2>&1; then
    echo "skipped: needs $drv (make bench-tools) and vdb_render (libopenvdb-tools)"
else
    shaft=$work/shaft.stl
    [ -f "$shaft" ] || "$HOVOX" generate cylinder -o "$shaft" >/dev/null
    model=$work/shaft256_render.vdb
    if [ ! -f "$model" ]; then
        "$HOVOX" voxelize "$shaft" --dims 256 -o "$work/shaft256.vdb" -q >/dev/null
        "$HOVOX" grade "$work/shaft256.vdb" -o "$work/shaft256_graded.vdb" --materials A,B,C --frf contour \
            --ranges 0,20.416,0 --f 'sin(0.1538*d)' --ms 0,0,1 --me 0,0.2,0.8 -q
        "$drv" --density-only "$work/shaft256_graded.vdb" "$model"
    fi
    for size in 16 1024 2048; do
        hv() { wall "$HOVOX" render "$model" --eye 75,200,200 --target 75,0,0 --up 0,0,1 --fov 44.8 \
            --size ${size}x$size -o "$work/shaft_hovox_$size.png" -q; }
        vr() { wall vdb_render "$model" "$work/shaft_vdb_$size.png" -res ${size}x$size -translate 75,200,200 \
            -lookat 75,0,0 -up 0,0,1 -step 1 -name density; }
        hv >/dev/null
        vr >/dev/null
        th="" tv=""
        i=0
        while [ $i -lt "$runs" ]; do
            th="$th $(hv)" tv="$tv $(vr)"
            i=$((i + 1))
        done
        # shellcheck disable=SC2086
        printf "%5s^2  hovox %7.3f s (%s)   vdb_render %7.3f s (%s)   ratio %sx\n" "$size" "$(median_of $th)" \
            "$(spread_of $th)" "$(median_of $tv)" "$(spread_of $tv)" "$(ratio "$(median_of $th)" "$(median_of $tv)")"
    done
    echo "(whole commands: load, render, PNG; runs alternate; images in $work/shaft_*.png)"
fi
