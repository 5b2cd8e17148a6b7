# issue 32.10 (3MF): a 430 kB package placing a 60,000-triangle strip 1024 times through a
# doubling component tree took `info` 6 GB and a minute under the default budget. Without a
# memory limit a package may not expand by repetition beyond 512 MiB or 256 times its size;
# with --max-memory the budget decides, before anything is placed (exit 3 either way, the peak
# resident size small, the message naming the counts)
cd "$TMP" || exit 1
/usr/bin/python3 - <<'PY'
import zipfile
CT = ('<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" '
      'ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" '
      'ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>')
RELS = ('<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship '
        'Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>'
        '</Relationships>')
n, levels = 30000, 10
v = ''.join('<vertex x="%d" y="%d" z="%d"/>' % (i, j, (i * 7 + j) % 5) for i in range(n + 1) for j in (0, 1))
t = ''.join('<triangle v1="%d" v2="%d" v3="%d"/><triangle v1="%d" v2="%d" v3="%d"/>'
            % (2 * i, 2 * i + 2, 2 * i + 1, 2 * i + 1, 2 * i + 2, 2 * i + 3) for i in range(n))
res = '<object id="1" name="strip"><mesh><vertices>%s</vertices><triangles>%s</triangles></mesh></object>' % (v, t)
for l in range(levels):
    res += ('<object id="%d"><components><component objectid="%d"/><component objectid="%d" '
            'transform="1 0 0 0 1 0 0 0 1 0 0 %d"/></components></object>' % (l + 2, l + 1, l + 1, 10 << l))
model = ('<model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources>%s'
         '</resources><build><item objectid="%d"/></build></model>' % (res, levels + 1))
with zipfile.ZipFile('repeat.3mf', 'w', zipfile.ZIP_DEFLATED) as z:
    for name, text in (('[Content_Types].xml', CT), ('_rels/.rels', RELS), ('3D/3dmodel.model', model)):
        z.writestr(zipfile.ZipInfo(name, (2024, 1, 1, 0, 0, 0)), text, zipfile.ZIP_DEFLATED)
PY
bound=204800
ldd "$HOVOX" | grep -q libasan && bound=1258291
for limit in "" "--max-memory 256M"; do
    /usr/bin/time -f %M -o peak.txt $HOVOX info $limit repeat.3mf 2>err.txt; echo "rc=$?"
    sed 's/^/  /' err.txt
    peak=$(tail -n 1 peak.txt)
    [ "$peak" -lt $bound ] && echo "peak resident size within its bound" || echo "peak resident size $peak KiB"
done
