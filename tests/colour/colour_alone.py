#!/usr/bin/python3
"""tests/colour/colour_alone.py SRC.3mf DST.3mf - a colour printer's package from hovox's painted one:
the <v:composite> and hovox's own materials and colour metadata taken out, so only the <v:color>
says what the part prints in (issue 29 item 3)."""
import re
import sys
import zipfile


def main(src_path, dst_path):
    src = zipfile.ZipFile(src_path)
    out = zipfile.ZipFile(dst_path, "w")
    for n in src.namelist():
        data = src.read(n)
        if n == "3D/3dmodel.model":
            text = re.sub(r"<v:composite .*?</v:composite>\s*", "", data.decode(), flags=re.S)
            text = re.sub(r'<metadata name="hovox:(materials|colour)">.*?</metadata>\s*', "", text, flags=re.S)
            data = text.encode()
        out.writestr(n, data)
    out.close()


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
