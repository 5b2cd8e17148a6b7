# issue 27: a package as Bambu Studio and OrcaSlicer write projects (Production extension
# required; the root's object of components names its meshes in /3D/Objects/object_1.model by
# p:path, that part with its own ids and base materials): core_in_shell.3mf moved 10 mm, read
# with its shell and core in their materials, gives the same layer bytes as core_in_shell.3mf
# given --translate 10,0,0.
$HOVOX info tests/data/good/production_parts.3mf | sed -n '/^build items/,$p'
$HOVOX layers tests/data/good/production_parts.3mf -o "$TMP/p" --layers 180:190 | grep '^  \|^wrote'
$HOVOX layers tests/data/good/core_in_shell.3mf --translate 10,0,0 -o "$TMP/c" --layers 180:190 -q >/dev/null
for f in "$TMP"/c/layer-*.png; do cmp "$f" "$TMP/p/$(basename "$f")" || echo "differs: $f"; done
echo "compared $(ls "$TMP"/c/layer-*.png | wc -l) layers"
