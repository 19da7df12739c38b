"""Nothing lost: existing files are never replaced unasked, one run per output folder, leftovers
of killed runs removed, folder problems reported before any work, cancel inside a large write."""
import json
import os
import re
import subprocess
import sys
import time

import numpy as np
import pytest
import tifffile

from easyidp_toolbox.core import ROI, ROISet
from easyidp_toolbox.core.errors import Cancelled, InputError
from easyidp_toolbox.core.files import LOCK_NAME, OutputFolder, check_output_folder
from easyidp_toolbox.core.raster.crop import crop_raster_by_rois
from easyidp_toolbox.tests.support.synthetic import rect, write_tif

O = (368000.0, 3956000.0)


def _rois(*named):
    return ROISet([ROI(n, [[rect(O[0] + a, O[1] - d, O[0] + c, O[1] - b)]]) for n, (a, b, c, d) in named],
                  "EPSG:32654")


@pytest.fixture
def dom(tmp_path):
    rgb = np.random.default_rng(1).integers(0, 255, (200, 200, 3), dtype=np.uint8)
    return write_tif(str(tmp_path / "dom.tif"), rgb, origin=O, pixel=0.5, tile=64)


PLOTS = (("A1", (1, 1, 20, 20)), ("A2", (30, 30, 60, 60)))


def test_existing_files_are_never_replaced_unasked(dom, tmp_path):
    out = tmp_path / "crops"
    out.mkdir()
    (out / "A1.tif").write_bytes(b"the user's own file")
    with pytest.raises(InputError, match=r"1 output file\(s\) already exist.*A1.tif.*Nothing was "
                                         r"written.*overwrite"):
        crop_raster_by_rois(dom, _rois(*PLOTS), str(out))
    assert sorted(os.listdir(out)) == ["A1.tif"]                     # A2 not written either
    assert (out / "A1.tif").read_bytes() == b"the user's own file"
    res = crop_raster_by_rois(dom, _rois(*PLOTS), str(out), overwrite=True)
    assert len(res.files) == 2 and tifffile.imread(str(out / "A1.tif")).shape[2] == 4


def test_a_second_run_into_the_same_folder_is_refused(dom, tmp_path):
    out = tmp_path / "crops"
    with OutputFolder(out):                     # another run (same process) holds the folder
        with pytest.raises(InputError, match="Another EasyIDP run .* is writing into"):
            crop_raster_by_rois(dom, _rois(*PLOTS), str(out))
    assert not (out / LOCK_NAME).exists()       # released on exit
    assert len(crop_raster_by_rois(dom, _rois(*PLOTS), str(out)).files) == 2
    assert not (out / LOCK_NAME).exists()


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_killed_runs_leave_nothing_the_next_run_keeps(dom, tmp_path):
    out = tmp_path / "crops"
    out.mkdir()
    pid = _dead_pid()
    (out / LOCK_NAME).write_text(json.dumps({"pid": pid, "host": os.uname().nodename,
                                             "started": "yesterday"}))
    stale = out / f".A9.{pid}-140000000000.part.tif"
    stale.write_bytes(b"half a crop")
    alive = out / f".A8.{os.getppid()}-1.part.tif"     # a live process's file: left alone
    alive.write_bytes(b"being written")
    res = crop_raster_by_rois(dom, _rois(*PLOTS), str(out))
    assert len(res.files) == 2 and not stale.exists() and alive.exists()
    assert not (out / LOCK_NAME).exists()


def test_kill_9_during_a_crop_leaves_only_what_the_next_run_removes(dom, tmp_path):
    """A real process killed with SIGKILL while it writes."""
    out = tmp_path / "crops"
    script = (
        "import sys, time\n"
        "from easyidp_toolbox.core.files import OutputFolder, atomic_output\n"
        "with OutputFolder(sys.argv[1]) as o:\n"
        "    with atomic_output(o.folder / 'A1.tif') as tmp:\n"
        "        tmp.write_bytes(b'partial')\n"
        "        print('writing', flush=True)\n"
        "        time.sleep(60)\n")
    proc = subprocess.Popen([sys.executable, "-c", script, str(out)], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "writing"
    proc.kill()
    proc.wait()
    assert any(n.endswith(".part.tif") for n in os.listdir(out)) and (out / LOCK_NAME).exists()
    crop_raster_by_rois(dom, _rois(*PLOTS), str(out))
    assert sorted(os.listdir(out)) == ["A1.tif", "A2.tif"]


def test_output_folder_problems_are_reported_before_any_work(dom, tmp_path):
    a_file = tmp_path / "plots.txt"
    a_file.write_text("not a folder")
    with pytest.raises(InputError, match="plots.txt' is a file, not a folder"):
        crop_raster_by_rois(dom, _rois(*PLOTS), str(a_file))
    with pytest.raises(InputError, match="cannot be created"):
        crop_raster_by_rois(dom, _rois(*PLOTS), str(a_file / "sub"))


def _tmpfs(path, options):
    """A real tmpfs mount (root); None when mounting is not permitted here."""
    path.mkdir()
    ok = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(path)],
                        capture_output=True).returncode == 0
    return path if ok else None


def test_read_only_and_full_disks_are_clear_errors(dom, tmp_path, monkeypatch):
    """Real read-only and 1 MiB file systems where this machine allows mounting (as in CI);
    otherwise the same errors raised by the OS are simulated (kind stated in the assertion)."""
    ro = _tmpfs(tmp_path / "ro", "ro,size=1m")
    small = _tmpfs(tmp_path / "small", "size=1m")
    try:
        if ro is None:                                  # simulated: EROFS from open()
            import errno
            real_open = open

            def fake_open(p, *a, **k):
                if "easyidp-probe" in str(p):
                    raise OSError(errno.EROFS, "Read-only file system")
                return real_open(p, *a, **k)
            monkeypatch.setattr("builtins.open", fake_open)
            ro = tmp_path / "ro"
        with pytest.raises(InputError, match="cannot be written to: it is on a read-only file system"):
            crop_raster_by_rois(dom, _rois(*PLOTS), str(ro))
        monkeypatch.undo()
        target = small if small is not None else tmp_path / "small"
        with pytest.raises(InputError, match="has only .* MiB free"):
            check_output_folder(target, min_free=2 * 2**20 if small is not None else 2**62)
    finally:
        for m in (tmp_path / "ro", tmp_path / "small"):
            if m.is_mount():
                subprocess.run(["umount", str(m)])


def test_cancel_during_one_large_write_removes_it_within_a_second(tmp_path, monkeypatch):
    """One ROI of 12 Mpixel: the cancel comes once its GeoTIFF has started to be encoded."""
    import easyidp_toolbox.core.raster.crop as crop_mod
    big = np.random.default_rng(2).integers(0, 255, (4000, 3000, 3), dtype=np.uint8)
    src = write_tif(str(tmp_path / "big.tif"), big, origin=O, pixel=0.5, tile=512)
    started = []
    real = crop_mod.write_geotiff

    def spy(*a, **k):
        started.append(time.perf_counter())
        return real(*a, **k)
    monkeypatch.setattr(crop_mod, "write_geotiff", spy)
    out = tmp_path / "o"
    with pytest.raises(Cancelled):
        crop_raster_by_rois(src, _rois(("all", (0, 0, 1500, 2000))), str(out),
                            is_cancelled=lambda: bool(started) and time.perf_counter() - started[0] > 0.05)
    elapsed = time.perf_counter() - started[0]
    assert os.listdir(out) == []                        # no file, no temporary file, no lock
    print(f"\ncancel honoured {elapsed:.2f} s after the large write started")


def test_demo_survey_never_replaces_a_users_file(tmp_path):
    from easyidp_toolbox.core.demo import make_demo_survey
    (tmp_path / "orthomosaic.tif").write_bytes(b"a user's orthomosaic")
    with pytest.raises(InputError, match="orthomosaic.tif.*Nothing was written"):
        make_demo_survey(str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == ["orthomosaic.tif"]
    with pytest.raises(Cancelled):                 # asked to replace: it gets as far as writing
        make_demo_survey(str(tmp_path), overwrite=True, is_cancelled=lambda: True)


def test_a_killed_runs_part_files_in_subfolders_are_removed(tmp_path):
    """Back-projection writes crops/<roi>/<photo>.json through hidden .part files: a kill leaves
    them one folder down, and the next run into crops/ removes them (issue 40)."""
    pid = _dead_pid()
    roi = tmp_path / "crops" / "A1"
    roi.mkdir(parents=True)
    stale = [roi / f".DJI_0001.{pid}-140000000000.part.json", roi / f".DJI_0001.{pid}-1.part.png"]
    for p in stale:
        p.write_bytes(b"{half")
    (roi / "DJI_0001.png").write_bytes(b"a finished crop")
    with OutputFolder(tmp_path / "crops", overwrite=True) as out:
        assert sorted(out.leftovers) == sorted(stale)
    assert sorted(os.listdir(roi)) == ["DJI_0001.png"]


_HOLD = ("import sys, time\n"
         "from easyidp_toolbox.core.files import LockHeld, hold_lock\n"
         "while time.time() < float(sys.argv[2]): pass\n"
         "try:\n"
         "    lock = hold_lock(sys.argv[1])\n"
         "except LockHeld as exc:\n"
         "    print('refused', exc.holder_text(), flush=True); sys.exit(3)\n"
         "print('held', flush=True)\n"
         "time.sleep(float(sys.argv[3]))\n"
         "lock.release()\n")


def test_runs_started_together_get_one_lock(tmp_path):
    """Six processes ask for one output's lock at the same instant: exactly one holds it, the
    others are refused naming the holder. A check-then-create lock let several through."""
    from easyidp_toolbox.core.files import file_lock_name
    lock = file_lock_name(tmp_path / "fp.gpkg")
    assert lock.name == ".fp.gpkg.easyidp.lock"
    go = time.time() + 1.0
    procs = [subprocess.Popen([sys.executable, "-c", _HOLD, str(lock), str(go), "1.5"],
                              stdout=subprocess.PIPE, text=True) for _ in range(6)]
    outs = [(p.wait(), p.stdout.read()) for p in procs]
    assert sorted(rc for rc, _ in outs) == [0, 3, 3, 3, 3, 3], outs
    assert all(re.match(r"refused process \d+ on ", o) for rc, o in outs if rc == 3), outs
    assert not lock.exists()                        # released by its holder


def test_a_killed_holders_lock_is_taken_over_and_threads_exclude_each_other(tmp_path):
    from easyidp_toolbox.core.files import LockHeld, hold_lock
    lock = tmp_path / ".x.easyidp.lock"
    proc = subprocess.Popen([sys.executable, "-c", _HOLD, str(lock), "0", "60"],
                            stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "held"
    with pytest.raises(LockHeld):
        hold_lock(lock)
    proc.kill()
    proc.wait()
    assert lock.exists()                            # the file stays, its lock went with the process
    mine = hold_lock(lock)
    with pytest.raises(LockHeld, match="x.easyidp.lock"):
        hold_lock(lock)                             # a second run in this process (a task thread)
    mine.release()
    assert not lock.exists()
