#!/usr/bin/python3
"""tests/io/scan/make_fuzz_corpus.py - seeds of the scan readers' fuzz corpora
(tests/fuzz/corpus/scan_{nifti,nrrd,metaimage,dicom}): a small phantom in each format
(make_phantom.py) and damaged copies (cut at several places, header fields and bytes changed).
Files are named by the SHA-1 of their bytes, as libFuzzer names what it finds.

    make_fuzz_corpus.py [REPO]   (default: the current directory)
"""
import glob
import hashlib
import os
import random
import subprocess
import sys
import tempfile

repo = sys.argv[1] if len(sys.argv) > 1 else "."
tmp = tempfile.mkdtemp()
subprocess.check_call(["/usr/bin/python3", os.path.join(repo, "tests/io/scan/make_phantom.py"), tmp,
                       "--size", "6,5,4", "--spacing", "12,14,20", "--affine", "rotated",
                       "--formats", "nii,nii.gz,nii2,nrrd,nrrd.raw,mha,dicom"])
rng = random.Random(30)


def put(kind, data):
    d = os.path.join(repo, "tests/fuzz/corpus", kind)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, hashlib.sha1(data).hexdigest()), "wb") as f:
        f.write(data)


def variants(kind, data, header_len, swaps=()):
    put(kind, data)
    for cut in (0, 1, 4, header_len // 2, header_len - 1, header_len, header_len + 7, len(data) - 1):
        put(kind, data[:max(0, cut)])
    for a, b in swaps:
        if a in data:
            put(kind, data.replace(a, b, 1))
    for _ in range(12):
        b = bytearray(data)
        for _ in range(rng.randint(1, 4)):
            i = rng.randrange(min(len(b), header_len + 16))
            b[i] = rng.randrange(256)
        put(kind, bytes(b))


def read(name):
    with open(os.path.join(tmp, name), "rb") as f:
        return f.read()


variants("scan_nifti", read("phantom.nii"), 352)
variants("scan_nifti", read("phantom2.nii"), 544)
put("scan_nifti", read("phantom.nii.gz"))
put("scan_nifti", read("phantom.nii.gz")[:40])
put("scan_nifti", read("phantom.nii.gz")[:-9])
nrrd = read("phantom_raw.nrrd")
variants("scan_nrrd", nrrd, nrrd.index(b"\n\n") + 2,
         [(b"sizes: 6 5 4", b"sizes: 6 5 40000"), (b"type: short", b"type: block"), (b"encoding: raw", b"encoding: ascii"),
          (b"space: left-posterior-superior", b"space: 3D-left-handed"), (b"(", b"(nan"), (b"endian: little\n", b"")])
gz = read("phantom.nrrd")
variants("scan_nrrd", gz, gz.index(b"\n\n") + 2)
put("scan_nrrd", b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 1\nencoding: ascii\n\n1 2 3 4\n")
put("scan_nrrd", b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 1\nencoding: ascii\n\n1 2 3e999 4\n")
mha = read("phantom.mha")
variants("scan_metaimage", mha, mha.index(b"LOCAL\n") + 6,
         [(b"DimSize = 6 5 4", b"DimSize = 6 5 400000"), (b"CompressedData = True", b"CompressedData = False"),
          (b"MET_SHORT", b"MET_DOUBLE"), (b"TransformMatrix = ", b"TransformMatrix = 0 0 0 0 0 0 0 0 0 ")])
for n in sorted(glob.glob(os.path.join(tmp, "dicom", "*")))[:2]:
    with open(n, "rb") as f:
        dcm = f.read()
    variants("scan_dicom", dcm, dcm.index(b"\xe0\x7f\x10\x00") + 12,
             [(b"1.2.840.10008.1.2.1\0", b"1.2.840.10008.1.2.4.50"), (b"\x10\x00\x02\x00US", b"\x10\x00\x02\x00UN")])
