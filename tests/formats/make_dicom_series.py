#!/usr/bin/env python3
"""Writes DICOM test series with pydicom (Debian python3-pydicom), for the DICOM reader's tests.

    make_dicom_series.py CASE OUT [SHARED_DATA]

CASE is one of the names in CASES below; OUT is created (a folder of slice files; for `ct`, also
OUT.nrrd, the same volume as an NRRD with the same geometry). Exit 3 when pydicom is missing (the
tests skip with that message), 2 on a bad CASE.

`ct`: a CT-like series of 279 slices made from ../shared/data/vtk_headsq/quarter (its 93 slices,
then reversed, then again), cropped to 64 columns x 60 rows, unsigned 16-bit with a Rescale Slope
and Intercept that change from slice to slice (the samples slope x stored + intercept are the
quarter's values exactly), axial LPS orientation, Pixel Spacing 0.5 (rows) x 0.75 (columns), 1.5 mm
between slices, written under shuffled file names with shuffled Instance Numbers.
The other cases are small series (32 x 30 x 8, int16) with one defect each.
"""
import os
import random
import sys

try:
    import numpy as np
    import pydicom
    from pydicom.dataset import Dataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid
except ImportError as e:  # the tests skip on this
    print(f"pydicom is not installed ({e}): apt-get install python3-pydicom", file=sys.stderr)
    sys.exit(3)

CT_IMAGE = "1.2.840.10008.5.1.4.1.1.2"


def slice_dataset(pixels, position, orientation, spacing, series_uid, description, instance, slope=None,
                  intercept=None, signed=False):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = CT_IMAGE
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = Dataset()
    ds.file_meta = meta
    ds.preamble = b"\0" * 128
    ds.is_little_endian = True
    ds.is_implicit_VR = False
    ds.SOPClassUID = CT_IMAGE
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.Modality = "CT"
    ds.PatientName = "Test^Phantom"
    ds.StudyInstanceUID = "1.2.826.0.1.3680043.8.498.1"
    ds.SeriesInstanceUID = series_uid
    ds.SeriesDescription = description
    ds.InstanceNumber = instance
    ds.ImagePositionPatient = [format(float(x), ".10g") for x in position]
    ds.ImageOrientationPatient = [format(float(x), ".10g") for x in orientation]
    ds.PixelSpacing = [format(float(x), ".10g") for x in spacing]
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.Rows, ds.Columns = pixels.shape
    ds.BitsAllocated = 16
    ds.BitsStored = 16
    ds.HighBit = 15
    ds.PixelRepresentation = 1 if signed else 0
    if slope is not None:
        ds.RescaleSlope = repr(float(slope))
        ds.RescaleIntercept = repr(float(intercept))
    ds.PixelData = pixels.astype("<i2" if signed else "<u2").tobytes()
    return ds


def write_series(out, vol, origin=(0.0, 0.0, 0.0), spacing=(1.0, 1.0, 1.5), orientation=(1, 0, 0, 0, 1, 0),
                 series_uid=None, description="test series", positions=None, names=None, rescale=None, signed=True):
    """vol[z][y][x]; spacing (x, y, z); one file per z slice."""
    os.makedirs(out, exist_ok=True)
    series_uid = series_uid or generate_uid()
    row, col = np.array(orientation[:3], float), np.array(orientation[3:], float)
    normal = np.cross(row, col)
    n = len(vol)
    if positions is None:
        positions = [np.array(origin, float) + normal * spacing[2] * k for k in range(n)]
    if names is None:
        names = [f"slice{k:04d}.dcm" for k in range(n)]
    instances = list(range(1, n + 1))
    random.Random(7).shuffle(instances)
    for k in range(n):
        slope, intercept = rescale[k] if rescale else (None, None)
        ds = slice_dataset(vol[k], positions[k], orientation, (spacing[1], spacing[0]), series_uid, description,
                           instances[k], slope, intercept, signed)
        ds.save_as(os.path.join(out, names[k]), write_like_original=False)
    return series_uid


def small(z=8, y=30, x=32):
    zz, yy, xx = np.meshgrid(np.arange(z), np.arange(y), np.arange(x), indexing="ij")
    return ((xx - x / 2) ** 2 + (yy - y / 2) ** 2 + ((zz - z / 2) * 3) ** 2).astype(np.int16)


def quarter(data):
    sl = []
    for k in range(1, 94):
        with open(os.path.join(data, "vtk_headsq", f"quarter.{k}"), "rb") as f:
            sl.append(np.frombuffer(f.read(), "<i2").reshape(64, 64))
    return np.array(sl)


def case_ct(out, data):
    q = quarter(data)
    vol = np.concatenate([q, q[::-1], q])[:, :60, :]  # 279 x 60 x 64 (z, y, x)
    n = len(vol)
    rescale, stored = [], []
    for k in range(n):
        slope, intercept = [(1.0, -1024.0), (0.5, -1024.0), (1.0, 0.0), (0.25, -10.0)][k % 4]
        s = (vol[k].astype(np.float64) - intercept) / slope
        assert np.all(s == np.round(s)) and s.min() >= 0 and s.max() <= 65535
        rescale.append((slope, intercept))
        stored.append(s.astype(np.uint16))
    names = [f"IM{v:06x}" for v in random.Random(11).sample(range(1 << 24), n)]  # shuffled: name order is not z order
    origin, spacing = (-24.0, -15.5, 20.0), (0.75, 0.5, 1.5)
    write_series(out, np.array(stored), origin=origin, spacing=spacing, description="CT head (quarter)", names=names,
                 rescale=rescale, signed=False)
    with open(out + ".nrrd", "wb") as f:
        f.write(("NRRD0004\ntype: float\ndimension: 3\nsizes: 64 60 %d\nendian: little\nencoding: raw\n"
                 "space: left-posterior-superior\nspace units: \"mm\" \"mm\" \"mm\"\nsample units: \"HU\"\nspace directions: (0.75,0,0) (0,0.5,0) (0,0,1.5)\n"
                 "space origin: (-24,-15.5,20)\n\n" % n).encode())
        f.write(vol.astype("<f4").tobytes())


def case_two_series(out, data):
    write_series(out, small(6, 30, 32), series_uid="1.2.826.0.1.3680043.8.498.100", description="first",
                 names=[f"a{k}" for k in range(6)])
    write_series(out, small(5, 16, 16) * 2, series_uid="1.2.826.0.1.3680043.8.498.200", description="second",
                 names=[f"b{k}" for k in range(5)])


def case_tilt(out, data):
    pos = [np.array([0.0, 0.3 * k, 1.5 * k]) for k in range(8)]  # y drifts along with z: gantry tilt
    write_series(out, small(), positions=pos)


def case_gap(out, data):
    pos = [np.array([0.0, 0.0, 1.5 * k]) for k in range(9) if k != 4]
    write_series(out, small(), positions=pos)


def case_duplicate(out, data):
    pos = [np.array([0.0, 0.0, 1.5 * k]) for k in range(7)] + [np.array([0.0, 0.0, 1.5 * 3])]
    write_series(out, small(), positions=pos)


def case_uneven(out, data):
    z = [0, 1.5, 3.0, 4.5, 6.3, 7.8, 9.3, 10.8]
    write_series(out, small(), positions=[np.array([0.0, 0.0, v]) for v in z])


def case_mixed_sizes(out, data):
    write_series(out, small(), description="mixed")
    uid = pydicom.dcmread(os.path.join(out, "slice0000.dcm")).SeriesInstanceUID
    write_series(out, small(1, 20, 32), series_uid=uid, positions=[np.array([0.0, 0.0, 1.5 * 8])], names=["odd.dcm"])


def case_mixed_orientation(out, data):
    write_series(out, small())
    path = os.path.join(out, "slice0003.dcm")
    ds = pydicom.dcmread(path)
    ds.ImageOrientationPatient = ["1", "0", "0", "0", "0", "-1"]
    ds.save_as(path, write_like_original=False)


def case_truncated(out, data):
    write_series(out, small())
    path = os.path.join(out, "slice0005.dcm")
    size = os.path.getsize(path)
    with open(path, "r+b") as f:
        f.truncate(size - 32 * 30)  # half the pixels gone


def case_no_pixels(out, data):
    write_series(out, small())
    path = os.path.join(out, "slice0002.dcm")
    ds = pydicom.dcmread(path)
    del ds.PixelData
    ds.save_as(path, write_like_original=False)


def case_rle(out, data):
    """The small series twice: uncompressed in OUT/plain, RLE Lossless in OUT/rle."""
    write_series(os.path.join(out, "plain"), small(), series_uid="1.2.826.0.1.3680043.8.498.300")
    write_series(os.path.join(out, "rle"), small(), series_uid="1.2.826.0.1.3680043.8.498.300")
    from pydicom.uid import RLELossless
    for name in os.listdir(os.path.join(out, "rle")):
        p = os.path.join(out, "rle", name)
        ds = pydicom.dcmread(p)
        ds.compress(RLELossless)
        ds.save_as(p, write_like_original=False)


def case_flipped(out, data):
    """The small series with the column direction posterior-to-anterior and slices stacked downwards
    (normal -z): y and z run backwards; OUT.nrrd holds the same index-order samples with the same
    (negative) directions, which the NRRD reader reverses to world order too."""
    vol = small()
    orientation = (1, 0, 0, 0, -1, 0)  # normal = (0, 0, -1)
    write_series(out, vol, origin=(-10.0, 20.0, 30.0), spacing=(0.75, 0.5, 1.5), orientation=orientation)
    with open(out + ".nrrd", "wb") as f:
        f.write(("NRRD0004\ntype: short\ndimension: 3\nsizes: 32 30 8\nendian: little\nencoding: raw\n"
                 "space: left-posterior-superior\nspace units: \"mm\" \"mm\" \"mm\"\nsample units: \"HU\"\nspace directions: (0.75,0,0) (0,-0.5,0) (0,0,-1.5)\n"
                 "space origin: (-10,20,30)\n\n").encode())
        f.write(vol.astype("<i2").tobytes())


def case_big(out, data):
    """For bench/MEASURED.md (no test uses it): quarter upsampled 8x in x and y (nearest) to 512 x 512,
    its 93 slices 4 times (372 slices, 195 MB of int16), identity rescale; OUT.nhdr + OUT.raw the same
    volume as one raw file."""
    q = np.repeat(np.repeat(quarter(data), 8, axis=1), 8, axis=2)
    vol = np.concatenate([q, q[::-1], q, q[::-1]])
    write_series(out, vol, spacing=(0.4, 0.4, 1.5), description="big", signed=True)
    vol.astype("<i2").tofile(out + ".raw")
    with open(out + ".nhdr", "w") as f:
        f.write("NRRD0004\ntype: short\ndimension: 3\nsizes: 512 512 %d\nendian: little\nencoding: raw\n"
                "space: left-posterior-superior\nspace directions: (0.4,0,0) (0,0.4,0) (0,0,1.5)\n"
                "space origin: (0,0,0)\ndata file: %s\n" % (len(vol), os.path.basename(out) + ".raw"))


CASES = {"ct": case_ct, "two-series": case_two_series, "tilt": case_tilt, "gap": case_gap, "duplicate": case_duplicate,
         "uneven": case_uneven, "mixed-sizes": case_mixed_sizes, "mixed-orientation": case_mixed_orientation,
         "truncated": case_truncated, "no-pixels": case_no_pixels, "rle": case_rle, "flipped": case_flipped, "big": case_big}

if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in CASES:
        print("usage: make_dicom_series.py {%s} OUT [SHARED_DATA]" % "|".join(CASES), file=sys.stderr)
        sys.exit(2)
    here = os.path.dirname(os.path.abspath(__file__))
    data = sys.argv[3] if len(sys.argv) > 3 else os.path.join(here, "..", "..", "..", "shared", "data")
    CASES[sys.argv[1]](sys.argv[2], data)
