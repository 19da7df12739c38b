"""Read many windows of a GeoTIFF in one top-to-bottom sweep.

Each tile or strip is decoded at most once for the whole window set, whatever the order of the
windows: the raster is walked in horizontal *bands* of block rows; the blocks of a band that any
window touches are decoded (in a thread pool, one band ahead), copied into the buffers of the
windows that overlap the band, then dropped. Memory is bounded by two bands of blocks plus the
windows open across a band boundary, not by the raster size.
"""
from concurrent.futures import Executor, ThreadPoolExecutor
from contextlib import contextmanager
import os
from typing import Callable, Dict, Iterator, List, NamedTuple, Optional, Sequence

import numpy as np

from .geotiff import GeoTiff
from .progress import Progress

BAND_MIN_ROWS = 256  # group strips so that a band has at least this many rows


class Window(NamedTuple):
    """A pixel window: top row, left column, number of rows and columns (inside the raster)."""
    row: int
    col: int
    rows: int
    cols: int


@contextmanager
def thread_pool(workers: Optional[int] = None) -> Iterator[Executor]:
    """A thread pool sized to the machine (zlib, imagecodecs and numpy copies release the GIL)."""
    pool = ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 2)
    try:
        yield pool
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def sweep_windows(tif: GeoTiff, windows: Sequence[Window],
                  consume: Callable[[int, np.ndarray], None],
                  progress: Progress, workers: Optional[int] = None) -> None:
    """Call ``consume(i, array)`` once per window with its (rows, cols, bands) pixel array.

    Windows complete in top-to-bottom order of their last row. Blocks are decoded by a pool of
    ``workers`` threads straight into the band's array, one band ahead of the copying, so the
    decoding of the next band overlaps ``consume`` (which may hand work to its own pool).
    ``progress`` gets 0–100 and is checked for cancellation once per band.
    """
    bh, bw = tif.block_height, tif.block_width
    per_band = max(1, -(-BAND_MIN_ROWS // bh))           # block rows per band
    n_bands = -(-tif.blocks_down // per_band)
    needed = np.zeros((tif.blocks_down, tif.blocks_across), dtype=bool)
    starts: Dict[int, List[int]] = {}
    ends: Dict[int, List[int]] = {}
    for i, w in enumerate(windows):
        br0, br1 = w.row // bh, (w.row + w.rows - 1) // bh
        needed[br0:br1 + 1, w.col // bw:(w.col + w.cols - 1) // bw + 1] = True
        starts.setdefault(br0 // per_band, []).append(i)
        ends.setdefault(br1 // per_band, []).append(i)
    bands_used = [b for b in range(n_bands) if needed[b * per_band:(b + 1) * per_band].any()]
    if not bands_used:
        return
    fd = os.open(tif.path, os.O_RDONLY)
    try:
        with thread_pool(workers) as pool:
            def submit(band: int):
                """Allocate the band's array and decode its needed blocks into it."""
                block_rows = needed[band * per_band:(band + 1) * per_band]
                top = band * per_band * bh
                bottom = min((band + 1) * per_band * bh, tif.height)
                cols = np.flatnonzero(block_rows.any(axis=0))
                left, right = int(cols[0]) * bw, min((int(cols[-1]) + 1) * bw, tif.width)
                arr = np.empty((bottom - top, right - left, tif.bands), dtype=tif.dtype)

                def decode(br: int, bc: int) -> None:
                    block = tif.read_block(fd, br, bc)
                    r, c = br * bh - top, bc * bw - left
                    arr[r:r + block.shape[0], c:c + block.shape[1]] = block

                futures = [pool.submit(decode, band * per_band + k, int(bc))
                           for k, row in enumerate(block_rows) for bc in np.flatnonzero(row)]
                return top, bottom, left, arr, futures

            open_bufs: Dict[int, np.ndarray] = {}
            pending = submit(bands_used[0])
            for k, band in enumerate(bands_used):
                progress.check()
                top, bottom, left, band_arr, futures = pending
                pending = submit(bands_used[k + 1]) if k + 1 < len(bands_used) else None
                for fut in futures:
                    fut.result()
                for i in starts.get(band, ()):
                    w = windows[i]
                    open_bufs[i] = np.empty((w.rows, w.cols, tif.bands), dtype=tif.dtype)
                for i, buf in open_bufs.items():
                    w = windows[i]
                    r0, r1 = max(w.row, top), min(w.row + w.rows, bottom)
                    if r1 > r0:
                        buf[r0 - w.row:r1 - w.row] = band_arr[r0 - top:r1 - top,
                                                              w.col - left:w.col + w.cols - left]
                del band_arr, futures
                for i in ends.get(band, ()):
                    consume(i, open_bufs.pop(i))
                progress.set(100.0 * (k + 1) / len(bands_used))
    finally:
        os.close(fd)
