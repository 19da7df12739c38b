"""Ragged arrays: many runs of different lengths (the vertices of rings, the rings of records)
stored end to end in one array, and the index arithmetic on them, vectorised.

A layout is given by ``offsets`` (n + 1,) int64, non-decreasing, ``offsets[0] == 0``: run i is
``[offsets[i], offsets[i + 1])``.
"""
import numpy as np


def offsets(lengths) -> np.ndarray:
    """(n + 1,) int64 offsets of runs of ``lengths`` (n,): 0, l0, l0 + l1, …"""
    lengths = np.asarray(lengths)
    out = np.zeros(len(lengths) + 1, np.int64)
    np.cumsum(lengths, out=out[1:])
    return out


def ranges(starts, stops) -> np.ndarray:
    """Concatenation of ``arange(starts[i], stops[i])`` for all i (int64)."""
    starts = np.asarray(starts, np.int64)
    lens = np.asarray(stops, np.int64) - starts
    total = int(lens.sum())
    if total == 0:
        return np.zeros(0, np.int64)
    return np.arange(total, dtype=np.int64) + np.repeat(starts - offsets(lens)[:-1], lens)


def run_of(offs: np.ndarray) -> np.ndarray:
    """(N,) the run each element belongs to."""
    return np.repeat(np.arange(len(offs) - 1), np.diff(offs))


def position_in_run(lengths: np.ndarray) -> np.ndarray:
    """(sum(lengths),) each element's position within its run: 0, 1, …, l0 − 1, 0, 1, …"""
    lengths = np.asarray(lengths, np.int64)
    return np.arange(int(lengths.sum()), dtype=np.int64) - np.repeat(offsets(lengths)[:-1], lengths)


def cyclic_next(offs: np.ndarray) -> np.ndarray:
    """(N,) the index of each element's successor in its run, the last one wrapping to the first
    (the other end of each ring edge)."""
    offs = np.asarray(offs, np.int64)
    nxt = np.arange(int(offs[-1]), dtype=np.int64) + 1
    full = np.diff(offs) > 0
    nxt[offs[1:][full] - 1] = offs[:-1][full]
    return nxt
