# issue 32 item 6: many build items. 20,000 items placing one 4-triangle object took `info` a
# minute (each copy's body name was found by trying "t (2)", "t (3)", ... in turn: quadratic);
# now linear, the copies named "t (2)" to "t (20000)" as before. 2,000,000 items (5 MB) are
# refused by the placement bound before anything is placed. The timeout catches a return of
# the quadratic rule.
cd "$TMP" || exit 1
/usr/bin/python3 - <<'PY'
import zipfile
CT = ('<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" '
      'ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" '
      'ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>')
RELS = ('<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship '
        'Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>'
        '</Relationships>')
TET = ('<object id="1" name="t"><mesh><vertices><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/>'
       '<vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/></vertices><triangles><triangle v1="0" v2="2" v3="1"/>'
       '<triangle v1="0" v2="1" v3="3"/><triangle v1="0" v2="3" v3="2"/><triangle v1="1" v2="2" v3="3"/>'
       '</triangles></mesh></object>')
for name, n in (('items20k.3mf', 20000), ('items2m.3mf', 2000000)):
    items = ''.join('<item objectid="1" transform="1 0 0 0 1 0 0 0 1 %d %d 0"/>' % (2 * (i % 1000), 2 * (i // 1000))
                    for i in range(n))
    model = ('<model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources>'
             '%s</resources><build>%s</build></model>' % (TET, items))
    with zipfile.ZipFile(name, 'w', zipfile.ZIP_DEFLATED) as z:
        for nm, text in (('[Content_Types].xml', CT), ('_rels/.rels', RELS), ('3D/3dmodel.model', model)):
            z.writestr(zipfile.ZipInfo(nm, (2024, 1, 1, 0, 0, 0)), text, zipfile.ZIP_DEFLATED)
PY
timeout 20 $HOVOX info items20k.3mf >info.txt; echo "rc=$?"
grep -c "^  t" info.txt
grep "^  t" info.txt | sed -n '1p;2p;$p'
timeout 20 $HOVOX info items2m.3mf; echo "rc=$?"
