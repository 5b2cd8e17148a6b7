# scripts/bench/10-info.sh - issue 2: `hovox info` vs admesh on 1,000,000 facets; start-up.
echo
echo "== info: 1,000,000-facet binary STL vs admesh (goal: <= 1.0x)"
mesh=$work/knot1m.stl
[ -f "$mesh" ] || "$HOVOX" generate knot facets=1000000 -o "$mesh"
t_h=$(median info_hovox "$HOVOX" info "$mesh")
t_a=$(median info_admesh admesh "$mesh")
echo "hovox info  $t_h s   (peak $(peak_rss "$HOVOX" info "$mesh") MiB)"
echo "admesh      $t_a s   (peak $(peak_rss admesh "$mesh") MiB)"
echo "ratio       $(ratio "$t_h" "$t_a")x admesh"
echo
echo "== start-up: hovox --version (goal: <= 20 ms)"
echo "hovox --version  $(median version "$HOVOX" --version) s"
