# gap3: blocks at x in [0, 9] and [14, 23] (1 mm voxels), rigid = 0.2 + 0.6u,
# flexible = 0.6 - 0.4u - 0.2v, tough = 0.2 - 0.2u + 0.2v with u = x/23, v = y/7.
# Header, comment, blank line, CRLF and blanks around values are accepted.
printf "x,y,z\r\n# a comment\n\n 0, 0, 0\n11.5,3,3\n23,7,7\r\n4.6,3.5,2\n" > "$TMP/p.csv"
$HOVOX probe tests/data/models/gap3.vdb 11.5,0,0 --points "$TMP/p.csv"
