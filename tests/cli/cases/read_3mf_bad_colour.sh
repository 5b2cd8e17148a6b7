# issue 29 item 3: a damaged colour in a 3MF Volumetric package (made from a painted model's own
# package): a <v:color> naming no function, a channel its function lacks, a colour sheet of another
# size, a colour sheet that is no picture. Each is one message naming the file, the part, the line
# and column and the element; exit 1; `layers` writes nothing.
$HOVOX voxelize samples/colour_cube.obj --voxel-size 1 --colour-depth 1 -o "$TMP/c.vdb" >/dev/null || exit 9
$HOVOX export "$TMP/c.vdb" -o "$TMP/c.3mf" --volumetric -q >/dev/null || exit 9
/usr/bin/python3 - "$TMP" <<'PY'
import re, struct, sys, zipfile, zlib
d = sys.argv[1]
src = zipfile.ZipFile(d + '/c.3mf')
model = src.read('3D/3dmodel.model').decode()
fn = re.search(r'<v:color functionid="(\d+)"', model).group(1)

def png(w, h):  # an RGBA picture of 16 bits, w x h, black
    raw = b''.join(b'\0' + b'\0' * 8 * w for _ in range(h))
    chunk = lambda t, b: struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b))
    return b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 16, 6, 0, 0, 0)) + \
        chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b'')

def write(name, model_text, sheet=None):
    out = zipfile.ZipFile(d + '/' + name, 'w')
    for n in src.namelist():
        data = src.read(n)
        if n == '3D/3dmodel.model':
            data = model_text.encode()
        elif sheet and n == '3D/volumetric/colour/sheet0003.png':
            data = sheet
        out.writestr(n, data)
    out.close()

write('no_function.3mf', model.replace('<v:color functionid="%s"' % fn, '<v:color functionid="999"'))
write('red.3mf', model.replace('channel="color"', 'channel="red"'))
write('size.3mf', model, png(5, 4))
write('text.3mf', model, b'<not a picture/>')
PY
for bad in no_function red size text; do
    $HOVOX layers "$TMP/$bad.3mf" -o "$TMP/out_$bad" --dpi 254,254 --layer-height 0.1
    echo "exit $?"
    [ -e "$TMP/out_$bad" ] && echo "$bad: a stack was written"
done
exit 0
