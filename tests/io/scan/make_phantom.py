#!/usr/bin/python3
"""tests/io/scan/make_phantom.py - the synthetic head phantom of hovox's scan tests (issue 30),
written by independent writers: NIfTI-1/2 by nibabel, a DICOM series by pydicom, NRRD and MetaImage
headers as their specifications spell them (teem's NRRD format, Kitware's MetaIO) over numpy data.

The phantom lives in world coordinates (RAS, mm): a head-like ellipsoid centred at CENTRE with
semi-axes AXES, in shells scaled by 1 (skin), 0.9 (skull) and 0.8 (brain):
    outside -1000 (air), skin 40, skull 1000, brain 30 (Hounsfield units).
Each voxel holds the mean of 4x4x4 samples over its cell (partial volume, as a scanner sees it),
rounded to an integer. The voxel grid is placed by an affine: 'ras' (axis-aligned), 'flip' (i and
k reversed), 'rotated' (turned 30 degrees about z and 12 about x), so a reader that honours the
affine finds the phantom at the same world place whatever the grid.

    make_phantom.py OUTDIR [--size NX,NY,NZ] [--spacing SX,SY,SZ] [--affine ras|flip|rotated]
        [--formats nii,nii.gz,nii2,nrrd,nrrd.raw,nhdr,mha,mhd,dicom] [--analytic]

writes OUTDIR/phantom.nii, phantom.nii.gz, phantom2.nii (NIfTI-2), phantom.nrrd (gzip),
phantom_raw.nrrd, phantom.nhdr + phantom.raw, phantom.mha (zlib), phantom.mhd + phantom.zraw... ,
dicom/ (one file per slice, in shuffled name order); --analytic prints the analytic volumes as JSON.
"""
import argparse
import json
import math
import os
import random
import sys
import zlib
import gzip

import numpy as np

CENTRE = np.array([2.0, -3.0, 5.0])
AXES = np.array([36.0, 44.0, 50.0])
SHELLS = [(1.0, 40.0), (0.9, 1000.0), (0.8, 30.0)]  # (scale, value inside it)
AIR = -1000.0


def value_at(p):
    """Values at world points p (..., 3)."""
    q = (p - CENTRE) / AXES
    r = np.sqrt((q * q).sum(axis=-1))
    v = np.full(r.shape, AIR)
    for s, val in SHELLS:
        v = np.where(r <= s, val, v)
    return v


def analytic():
    """Volumes (mm^3) of the regions above each iso a test uses."""
    full = 4.0 / 3.0 * math.pi * AXES.prod()
    return {"head": full, "skull_outer": full * 0.9 ** 3, "brain": full * 0.8 ** 3,
            "skull": full * (0.9 ** 3 - 0.8 ** 3), "centre": CENTRE.tolist(), "axes": AXES.tolist(),
            "shells": SHELLS, "air": AIR}


def make_affine(kind, size, spacing):
    """4x4 index -> RAS affine whose grid covers the phantom, centred on CENTRE."""
    n = np.array(size, float)
    s = np.array(spacing, float)
    if kind == "ras":
        R = np.eye(3)
    elif kind == "flip":
        R = np.diag([-1.0, 1.0, -1.0])
    elif kind == "rotated":
        a, b = math.radians(30), math.radians(12)
        Rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
        Rx = np.array([[1, 0, 0], [0, math.cos(b), -math.sin(b)], [0, math.sin(b), math.cos(b)]])
        R = Rz @ Rx
    else:
        raise SystemExit("unknown affine " + kind)
    M = R * s  # columns scaled by spacing
    origin = CENTRE - M @ ((n - 1) / 2)
    A = np.eye(4)
    A[:3, :3] = M
    A[:3, 3] = origin
    # round to what a DICOM decimal string holds, so every format carries the same numbers
    return np.array([[float("%.10g" % v) for v in row] for row in A])


def sample(size, A, sub=4):
    nx, ny, nz = size
    out = np.zeros(size, np.float64)
    offs = (np.arange(sub) + 0.5) / sub - 0.5
    ii, jj = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    for k in range(nz):
        acc = np.zeros((nx, ny))
        for a in offs:
            for b in offs:
                for c in offs:
                    idx = np.stack([ii + a, jj + b, np.full(ii.shape, k + c)], axis=-1)
                    p = idx @ A[:3, :3].T + A[:3, 3]
                    acc += value_at(p)
        out[:, :, k] = acc / sub ** 3
    return np.rint(out).astype(np.int16)


def lps(A):
    L = A.copy()
    L[0, :] *= -1
    L[1, :] *= -1
    return L


def fmt(v):
    return "%.17g" % v


def write_nrrd(path, data, A, encoding, detached=None):
    L = lps(A)
    dirs = " ".join("(%s)" % ",".join(fmt(L[r, a]) for r in range(3)) for a in range(3))
    head = ["NRRD0004", "# written by hovox tests/io/scan/make_phantom.py", "type: short", "dimension: 3",
            "space: left-posterior-superior", "sizes: %d %d %d" % data.shape, "space directions: " + dirs,
            "kinds: domain domain domain", "endian: little", "encoding: " + encoding,
            "space origin: (%s)" % ",".join(fmt(L[r, 3]) for r in range(3)),
            'space units: "mm" "mm" "mm"']
    raw = data.astype("<i2").tobytes(order="F")
    body = gzip.compress(raw) if encoding == "gzip" else raw
    if detached:
        head.append("data file: " + os.path.basename(detached))
        with open(detached, "wb") as f:
            f.write(body)
        with open(path, "w") as f:
            f.write("\n".join(head) + "\n")
    else:
        with open(path, "wb") as f:
            f.write(("\n".join(head) + "\n\n").encode())
            f.write(body)


def write_mha(path, data, A, compressed, detached=None):
    L = lps(A)
    s = np.sqrt((A[:3, :3] ** 2).sum(axis=0))
    D = L[:3, :3] / s  # columns: unit directions of the axes
    tm = " ".join(fmt(D[r, a]) for a in range(3) for r in range(3))  # axis 0's direction first
    raw = data.astype("<i2").tobytes(order="F")
    body = zlib.compress(raw) if compressed else raw
    head = ["ObjectType = Image", "NDims = 3", "BinaryData = True", "BinaryDataByteOrderMSB = False",
            "CompressedData = %s" % ("True" if compressed else "False")]
    if compressed:
        head.append("CompressedDataSize = %d" % len(body))
    head += ["TransformMatrix = " + tm, "Offset = " + " ".join(fmt(L[r, 3]) for r in range(3)),
             "CenterOfRotation = 0 0 0", "AnatomicalOrientation = RAI",
             "ElementSpacing = " + " ".join(fmt(v) for v in s), "DimSize = %d %d %d" % data.shape,
             "ElementType = MET_SHORT",
             "ElementDataFile = " + (os.path.basename(detached) if detached else "LOCAL")]
    text = ("\n".join(head) + "\n").encode()
    if detached:
        with open(detached, "wb") as f:
            f.write(body)
        with open(path, "wb") as f:
            f.write(text)
    else:
        with open(path, "wb") as f:
            f.write(text + body)


def write_dicom(dirpath, data, A, seed=7):
    import pydicom
    from pydicom.dataset import Dataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid

    os.makedirs(dirpath, exist_ok=True)
    L = lps(A)
    s = np.sqrt((A[:3, :3] ** 2).sum(axis=0))
    row_dir = L[:3, 0] / s[0]  # along a row: column index i
    col_dir = L[:3, 1] / s[1]  # down a column: row index j
    series = generate_uid(entropy_srcs=["hovox phantom series"])
    study = generate_uid(entropy_srcs=["hovox phantom study"])
    names = list(range(data.shape[2]))
    random.Random(seed).shuffle(names)
    for k in range(data.shape[2]):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"  # CT Image Storage
        meta.MediaStorageSOPInstanceUID = generate_uid(entropy_srcs=["hovox phantom", str(k)])
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        ds = Dataset()
        ds.file_meta = meta
        ds.is_little_endian = True
        ds.is_implicit_VR = False
        ds.SOPClassUID = meta.MediaStorageSOPClassUID
        ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
        ds.Modality = "CT"
        ds.PatientName = "Phantom^Head"
        ds.StudyInstanceUID = study
        ds.SeriesInstanceUID = series
        ds.InstanceNumber = k + 1
        pos = L[:3, :3] @ np.array([0.0, 0.0, k]) + L[:3, 3]
        ds.ImagePositionPatient = ["%.10g" % v for v in pos]
        ds.ImageOrientationPatient = ["%.10g" % v for v in list(row_dir) + list(col_dir)]
        ds.PixelSpacing = ["%.10g" % s[1], "%.10g" % s[0]]  # row spacing, column spacing
        ds.SliceThickness = "%.10g" % s[2]
        ds.SamplesPerPixel = 1
        ds.PhotometricInterpretation = "MONOCHROME2"
        ds.Rows = data.shape[1]
        ds.Columns = data.shape[0]
        ds.BitsAllocated = 16
        ds.BitsStored = 12
        ds.HighBit = 11
        ds.PixelRepresentation = 0
        ds.RescaleIntercept = "-1024"
        ds.RescaleSlope = "1"
        ds.RescaleType = "HU"
        # a sequence of undefined length before the pixels, as scanners write them
        item = Dataset()
        item.CodeValue = "T-D1100"
        item.CodingSchemeDesignator = "SRT"
        item.CodeMeaning = "Head"
        ds.AnatomicRegionSequence = [item]
        stored = (data[:, :, k].astype(np.int32) + 1024).T.astype("<u2")  # (rows, cols)
        ds.PixelData = stored.tobytes()
        ds.preamble = b"\0" * 128
        pydicom.dcmwrite(os.path.join(dirpath, "IM%05d.dcm" % (names[k] * 37 % 99991)), ds,
                         write_like_original=False)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--size", default="80,96,72")
    ap.add_argument("--spacing", default="1,1,1.5")
    ap.add_argument("--affine", default="ras")
    ap.add_argument("--formats", default="nii,nii.gz,nii2,nrrd,nrrd.raw,nhdr,mha,mhd,dicom")
    ap.add_argument("--analytic", action="store_true")
    a = ap.parse_args()
    size = tuple(int(v) for v in a.size.split(","))
    spacing = tuple(float(v) for v in a.spacing.split(","))
    os.makedirs(a.outdir, exist_ok=True)
    A = make_affine(a.affine, size, spacing)
    data = sample(size, A)
    import nibabel as nib
    for f in a.formats.split(","):
        o = a.outdir
        if f in ("nii", "nii.gz"):
            img = nib.Nifti1Image(data, A)
            img.set_sform(A, code=1)
            img.set_qform(A, code=1)
            nib.save(img, os.path.join(o, "phantom." + f))
        elif f == "nii2":
            img = nib.Nifti2Image(data, A)
            img.set_sform(A, code=1)
            nib.save(img, os.path.join(o, "phantom2.nii"))
        elif f == "nrrd":
            write_nrrd(os.path.join(o, "phantom.nrrd"), data, A, "gzip")
        elif f == "nrrd.raw":
            write_nrrd(os.path.join(o, "phantom_raw.nrrd"), data, A, "raw")
        elif f == "nhdr":
            write_nrrd(os.path.join(o, "phantom.nhdr"), data, A, "raw", os.path.join(o, "phantom.raw"))
        elif f == "mha":
            write_mha(os.path.join(o, "phantom.mha"), data, A, True)
        elif f == "mhd":
            write_mha(os.path.join(o, "phantom.mhd"), data, A, False, os.path.join(o, "phantom_mhd.raw"))
        elif f == "dicom":
            write_dicom(os.path.join(o, "dicom"), data, A)
        else:
            raise SystemExit("make_phantom.py: unknown format " + f)
    if a.analytic:
        json.dump(analytic(), sys.stdout)
        print()


if __name__ == "__main__":
    main()
