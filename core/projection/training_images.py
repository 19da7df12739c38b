"""The images of a training set (:mod:`.training_set`): which photos go in (each decoded
once to check it), and their files: whole photos copied byte for byte, tiles cut from one
decode per photo (PNG), or, for physical values, float32 TIFFs of the values
(:mod:`..radiometry`: whole photos and tiles alike; PNG and JPEG cannot hold them)."""
import os
import shutil
from typing import Dict

import numpy as np

from ..errors import InputError
from ..files import atomic_output, write_bytes
from ..photos import DecodedPhotos
from ..radiometry import PhotoValues, tiff_extratags
from .photo_crops import PNG_FAST, TIFF_LEVEL

IMAGE_MAGIC = (b"\xff\xd8", b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+", b"\x89PNG",
               b"\x00\x00\x00\x0cjP  ", b"\xff\x4f\xff\x51", b"RIFF", b"BM")
"""How a photo file may start: JPEG, TIFF (and DNG), BigTIFF, PNG, JPEG 2000, WebP, BMP."""


def photo_problem(path: str) -> str:
    """Why the file cannot be a complete photo ("" when it may be): it starts like no image
    format (a text file named .JPG; never handed to a decoder that tries every codec), or it is
    a JPEG without its end-of-image marker (truncated; zero padding allowed)."""
    with open(path, "rb") as fh:
        head = fh.read(12)
        if not any(head.startswith(m) for m in IMAGE_MAGIC):
            return (f"{path} is not an image (it starts with {head[:8]!r}): put the photo "
                    "itself there")
        if not head.startswith(b"\xff\xd8"):
            return ""
        fh.seek(0, os.SEEK_END)
        fh.seek(max(0, fh.tell() - 65536))
        if not fh.read().rstrip(b"\x00").endswith(b"\xff\xd9"):
            return (f"the JPEG {path} is truncated (no end-of-image marker): copy it again from "
                    "the card or the drone")
    return ""


def decodable_photos(images, found, bp, result, prog, decode=None) -> Dict[str, tuple]:
    """{photo label: (width, height)} of the photos that decode at the camera's size (with
    ``decode``: :func:`..radiometry.photo_decoder`'s, None as stored); the others go to
    ``result.skipped_photos``. Photos cut or converted are decoded again when written."""
    labels = sorted({x[2] for x in images})
    size = {lab: tuple(int(v) for v in bp.image_sizes[bp.photo_labels.index(lab)]) for lab in labels}
    paths, why = [], []
    for lab in labels:
        try:
            problem = photo_problem(found[lab])
        except OSError as exc:
            problem = f"{found[lab]} cannot be read ({exc.strerror})"
        why.append(problem)
        paths.append(None if problem else found[lab])
    good = {}
    with DecodedPhotos(paths, [size[lab] for lab in labels], missing=why, decode=decode) as decoded:
        for k, img, reason in decoded:
            if img is None:
                result.skipped_photos[labels[k]] = f"left out with its labels: {reason}"
            else:
                good[labels[k]] = size[labels[k]]
            prog.set(65 + 10 * (k + 1) / max(len(labels), 1))
    return good


def write_images(folder, images, found, good, result, prog, decoding=("stored", None)):
    """Whole photos copied byte for byte (after their decode check); tiles cut from one decode
    per photo; with ``decoding`` (values, :func:`..radiometry.photo_decoder`'s decoder) for
    physical values, every image a float32 TIFF of its window of the values."""
    import imagecodecs
    values, decode = decoding
    by_label = {}
    for s, im, label, win, _ in images:
        by_label.setdefault(label, []).append((s, im, win))

    def place(s, im, data_writer):
        main = folder / "images" / s / im.file_name
        data_writer(main)
        link = folder / "yolo_detect" / "images" / s / im.file_name
        with atomic_output(link) as tmp:
            try:
                os.link(main, tmp)
            except OSError:
                shutil.copyfile(main, tmp)
        result.files += [str(main), str(link)]

    labels = sorted(by_label)
    cut = [lab for lab in labels if decode is not None or by_label[lab][0][2] is not None]
    for lab in labels:
        if lab in cut:
            continue
        for s, im, _ in by_label[lab]:
            def copy(dst, src=found[lab]):
                with atomic_output(dst) as tmp:
                    shutil.copyfile(src, tmp)
            place(s, im, copy)
        prog.check()
    if not cut:
        return
    with DecodedPhotos([found[lab] for lab in cut], [good[lab] for lab in cut],
                       decode=decode) as decoded:
        for k, img, why in decoded:
            lab = cut[k]
            if img is None:             # decoded at the check, not now: the file changed
                raise InputError(f"The photo {found[lab]} changed while the training set was "
                                 f"written: {why}. Run again with overwrite.")
            pv = None
            if isinstance(img, PhotoValues):
                pv, img = img, img.masked()
            elif img.dtype != np.uint8:
                raise InputError(f"Photo {lab}: tiles are written as 8-bit PNG, but the photo "
                                 f"is {img.dtype}; export whole photos (tile size 0).")
            for s, im, win in by_label[lab]:
                r0, c0 = win or (0, 0)
                tile = np.ascontiguousarray(img[r0:r0 + im.height, c0:c0 + im.width])
                if pv is None:
                    place(s, im, lambda dst: write_bytes(dst, imagecodecs.png_encode(tile, **PNG_FAST)))
                else:
                    place(s, im, lambda dst: _write_values(dst, tile, values, pv))
            prog.set(75 + 20 * (k + 1) / len(cut))


def _write_values(path, arr: np.ndarray, values: str, pv: PhotoValues) -> None:
    """A float32 TIFF of ``arr`` (values of ``pv``, NaN where not valid) with the unit and note
    in GDAL's metadata (:func:`..radiometry.tiff_extratags`), atomically."""
    import tifffile
    with atomic_output(path) as tmp:
        tifffile.imwrite(tmp, arr, photometric="minisblack", planarconfig="contig",
                         compression="zlib", compressionargs={"level": TIFF_LEVEL},
                         extratags=tiff_extratags(values, pv), metadata=None)
