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
from ..progress import Progress

BAND_MIN_ROWS = 256    # group strips so that a cell has at least this many rows
CELL_MAX_WIDTH = 4096  # pixels of tile columns per cell (strips are one cell wide)


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

    The raster is walked in *cells* (a band of block rows × at most ``CELL_MAX_WIDTH`` pixels
    of block columns) in row-major order. A cell's blocks that any window touches are decoded
    by a pool of ``workers`` threads straight into the cell's array, one cell ahead of the
    copying, so decoding overlaps ``consume`` (which may hand work to its own pool). A window
    is complete after its bottom-right cell. ``progress`` gets 0–100 and is checked for
    cancellation once per cell.
    """
    bh, bw = tif.block_height, tif.block_width
    per_band = max(1, -(-BAND_MIN_ROWS // bh))             # block rows per cell
    per_cell = max(1, CELL_MAX_WIDTH // bw)                 # block columns per cell
    n_chunks = -(-tif.blocks_across // per_cell)
    needed = np.zeros((tif.blocks_down, tif.blocks_across), dtype=bool)
    starts: Dict[int, List[int]] = {}
    ends: Dict[int, List[int]] = {}
    for i, w in enumerate(windows):
        br0, br1 = w.row // bh, (w.row + w.rows - 1) // bh
        bc0, bc1 = w.col // bw, (w.col + w.cols - 1) // bw
        needed[br0:br1 + 1, bc0:bc1 + 1] = True
        starts.setdefault((br0 // per_band) * n_chunks + bc0 // per_cell, []).append(i)
        ends.setdefault((br1 // per_band) * n_chunks + bc1 // per_cell, []).append(i)
    n_cells = -(-tif.blocks_down // per_band) * n_chunks
    cells = [c for c in range(n_cells) if _cell_blocks(needed, c, per_band, per_cell, n_chunks).any()]
    if not cells:
        return
    fd = os.open(tif.path, os.O_RDONLY)
    try:
        with thread_pool(workers) as pool:
            def submit(cell: int):
                """Allocate the cell's array and decode its needed blocks into it."""
                band, chunk = divmod(cell, n_chunks)
                blocks = _cell_blocks(needed, cell, per_band, per_cell, n_chunks)
                br0, bc0 = band * per_band, chunk * per_cell
                used = np.flatnonzero(blocks.any(axis=0))
                top, bottom = br0 * bh, min((br0 + blocks.shape[0]) * bh, tif.height)
                left = (bc0 + int(used[0])) * bw
                right = min((bc0 + int(used[-1]) + 1) * bw, tif.width)
                arr = np.empty((bottom - top, right - left, tif.bands), dtype=tif.dtype)

                def decode(br: int, bc: int) -> None:
                    block = tif.read_block(fd, br, bc)
                    r, c = br * bh - top, bc * bw - left
                    arr[r:r + block.shape[0], c:c + block.shape[1]] = block

                futures = [pool.submit(decode, br0 + r, bc0 + int(c))
                           for r, row in enumerate(blocks) for c in np.flatnonzero(row)]
                return cell, top, bottom, left, right, arr, futures

            open_bufs: Dict[int, np.ndarray] = {}
            pending = submit(cells[0])
            for k in range(len(cells)):
                progress.check()
                cell, top, bottom, left, right, cell_arr, futures = pending
                pending = submit(cells[k + 1]) if k + 1 < len(cells) else None
                for fut in futures:
                    fut.result()
                for i in starts.get(cell, ()):
                    w = windows[i]
                    open_bufs[i] = np.empty((w.rows, w.cols, tif.bands), dtype=tif.dtype)
                for i, buf in open_bufs.items():
                    w = windows[i]
                    r0, r1 = max(w.row, top), min(w.row + w.rows, bottom)
                    c0, c1 = max(w.col, left), min(w.col + w.cols, right)
                    if r1 > r0 and c1 > c0:
                        buf[r0 - w.row:r1 - w.row, c0 - w.col:c1 - w.col] = \
                            cell_arr[r0 - top:r1 - top, c0 - left:c1 - left]
                del cell_arr, futures
                for i in ends.get(cell, ()):
                    consume(i, open_bufs.pop(i))
                progress.set(100.0 * (k + 1) / len(cells))
    finally:
        os.close(fd)


def _cell_blocks(needed: np.ndarray, cell: int, per_band: int, per_cell: int,
                 n_chunks: int) -> np.ndarray:
    """The ``needed`` flags of the blocks of one cell (a view)."""
    band, chunk = divmod(cell, n_chunks)
    return needed[band * per_band:(band + 1) * per_band, chunk * per_cell:(chunk + 1) * per_cell]
