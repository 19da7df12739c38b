"""A season of surveys → traits per ROI per date, one job per (survey, file) on an executor.

Jobs: the ground raster of the season (when given) gives a plane per ROI; each orthomosaic,
DSM and point cloud is read once, computing every ROI's traits in its one pass (see
:mod:`.jobs`). Orthomosaic jobs start at once; DSM and point-cloud jobs when the ground is known.
Results are gathered into one tidy table, in ROI order, then date, then trait, the same whatever
the executor and the order in which jobs finish.
"""
import math
import os
import shutil
import tempfile
import time
from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Sequence, Tuple, Union

from ..deprecation import renamed_parameters
from ..errors import Cancelled, EasyIDPError, ROIError
from ..files import check_not_inputs
from ..progress import as_progress
from ..roi import ROISet
from . import traits as tr
from .executors import open_runner, wait_any
from .jobs import Job, JobResult, run_job
from .series import RowProblem, Survey, SurveyTable, read_survey_table

KIND_TRAITS = {"orthomosaic": ("cover", "bands", "index"), "dsm": ("height",),
               "point_cloud": ("cloud",)}
TRAIT_ORDER = ("height_", "cover", "exg", "ndvi", "mean_", "cloud_points", "cloud_height_")
MAX_NAMED = 20   # ROIs named per message


@dataclass
class SeasonResult:
    """``rows``: the long table (roi, date, trait, value), only values that exist, in ROI order,
    then date, then trait; ``problems``: rows and files left out; ``notes``: other facts
    (cover thresholds, ROIs without values); ``jobs``: every job's result (timings, worker,
    peak memory)."""
    rois: ROISet
    dates: List[str]
    traits: List[str]
    rows: List[Tuple[str, str, str, float]]
    problems: List[RowProblem] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    jobs: List[JobResult] = field(default_factory=list)
    executor: str = ""
    seconds: float = 0.0
    inputs: List[str] = field(default_factory=list)   # files read (never written over)

    def table(self) -> Dict[Tuple[str, str], Dict[str, float]]:
        """{(roi, date): {trait: value}}."""
        out: Dict[Tuple[str, str], Dict[str, float]] = {}
        for roi, date, trait, value in self.rows:
            out.setdefault((roi, date), {})[trait] = value
        return out

    def latest(self) -> List[Tuple[Optional[str], Dict[str, float]]]:
        """Per ROI (in order): its latest date with values and the traits of that date
        ((None, {}) for an ROI without any value)."""
        by_roi: Dict[str, Tuple[str, Dict[str, float]]] = {}
        for (roi, date), values in self.table().items():
            if roi not in by_roi or date > by_roi[roi][0]:
                by_roi[roi] = (date, values)
        return [by_roi.get(r.name, (None, {})) for r in self.rois]


@renamed_parameters(ground_crs="ground_source_crs")
def run_season(table: Union[str, SurveyTable, Sequence[Survey]], rois: ROISet,
               traits: Optional[Sequence[str]] = None,
               percentiles: Sequence[float] = tr.DEFAULT_PERCENTILES,
               ground: Optional[str] = None, ground_source_crs=None,
               ground_percentile: float = 2.0,
               cover_threshold: Optional[float] = None, crops: Optional[str] = None,
               overwrite: bool = False, workers: Optional[int] = None,
               scheduler: Optional[str] = None,
               local_cluster: bool = False, progress=None, is_cancelled=None,
               log: Optional[Callable[[str], None]] = None) -> SeasonResult:
    """Traits of every ROI at every date of the season.

    On cancellation pending jobs are cancelled, running ones stop at their next block, and
    :class:`Cancelled` is raised. Bad rows and files are reported in ``result.problems`` and
    left out.

    Parameters
    ----------
    table : str, SurveyTable or sequence of Survey
        The survey table: a CSV path, a :class:`SurveyTable` or the surveys.
    rois : ROISet
        The ROIs.
    traits : sequence of str, optional
        A subset of :data:`traits.TRAIT_GROUPS` (default all).
    percentiles : sequence of float
        The height percentiles (0–100) of the height traits.
    ground : str, optional
        A bare-soil DSM or DTM (GeoTIFF) of the season, heights in the DSMs' and clouds'
        vertical reference; without it, each ROI's ground is the plane through its own
        ``ground_percentile``-th percentile heights (see :mod:`.ground`).
    ground_source_crs : CRS, optional
        The CRS to assume for ``ground``, instead of the one its GeoKeys give.
    ground_percentile : float
        The percentile (0–100) of an ROI's heights taken as its ground without ``ground``.
    cover_threshold : float, optional
        The vegetation index above which a pixel is canopy (default: Otsu per orthomosaic).
    crops : str, optional
        A folder for the crops, ``<date>/<kind>/``.
    overwrite : bool
        Replace existing crops.
    workers : int, optional
        Local processes (default: the cores), or the processes of a local Dask cluster.
    scheduler : str, optional
        A Dask scheduler address ``tcp://host:port``.
    local_cluster : bool
        Run on a Dask LocalCluster of ``workers`` processes.
    progress : callable or Progress, optional
        Called with the percent done (0–100) after every job.
    is_cancelled : callable, optional
        Polled; returns True to stop.
    log : callable, optional
        Called with each line of the run's log.

    Returns
    -------
    SeasonResult
        The traits per ROI per date, with the problems met.
    """
    t0 = time.perf_counter()
    say = log or (lambda _m: None)
    prog = as_progress(progress, is_cancelled)
    if isinstance(table, str):
        table = read_survey_table(table)
    elif not isinstance(table, SurveyTable):
        table = SurveyTable(list(table))
    traits = tr.check_traits(traits)
    percentiles = tr.check_percentiles(percentiles)
    rois = _checked_rois(rois)
    if ground is not None and not os.path.isfile(ground):
        raise EasyIDPError(f"Ground raster not found: {ground}")
    if cover_threshold is not None and not math.isfinite(cover_threshold):
        raise EasyIDPError(f"The cover threshold must be a number (got {cover_threshold}).")
    if "cover" in traits and cover_threshold is None:
        try:
            import skimage.filters  # noqa: F401 (Otsu's threshold, in the jobs)
        except ImportError as exc:
            raise EasyIDPError(f"Canopy cover with an automatic threshold needs scikit-image "
                               f"({exc}): pip install scikit-image (Debian/Ubuntu: apt install "
                               "python3-skimage), or give a cover threshold.") from None

    problems = list(table.problems)
    notes: List[str] = []
    if any(s.project for s in table.surveys):
        notes.append("the 'project' column is read but no trait uses it yet (backward "
                     "projection of a season comes later)")
    base = dict(rois=rois, traits=traits, percentiles=percentiles,
                ground_percentile=ground_percentile, cover_threshold=cover_threshold,
                overwrite=overwrite)
    first, later = _plan(table, traits, crops, ground, base)
    if not first and not later:
        detail = "; ".join(str(p) for p in problems[:5])
        raise EasyIDPError("Nothing to compute: no survey row has a readable file for the traits "
                           f"asked ({', '.join(traits)}). {detail}")
    if ground and later:
        first.insert(0, Job(key="ground", kind="ground", path=ground, crs=ground_source_crs, **base))
    with open_runner(workers, scheduler, local_cluster, log=say) as runner:
        results = _execute(runner, first, later, not scheduler, prog, say)

    rows, dup = _long_rows(rois, results, problems, notes)
    if dup:
        notes.append(f"{dup} value(s) given by two rows of the same date for the same ROI: the "
                     "first row's are kept")
    dates = sorted({d for _, d, _, _ in rows})
    names = sorted({t for _, _, t, _ in rows}, key=_trait_key)
    index = {t: k for k, t in enumerate(names)}
    order = {r.name: k for k, r in enumerate(rois)}
    rows.sort(key=lambda r: (order[r[0]], r[1], index[r[2]]))
    results.sort(key=lambda r: (r.row, r.kind))
    return SeasonResult(rois, dates, names, rows, problems, notes, results, runner.label,
                        time.perf_counter() - t0, season_inputs(table, ground))


def _checked_rois(rois: ROISet) -> ROISet:
    rois.validate()
    seen, dups = set(), []
    for r in rois:
        if r.name in seen:
            dups.append(r.name)
        seen.add(r.name)
    if dups:
        raise ROIError(f"ROI names must be unique in a season table; repeated: "
                       f"{', '.join(sorted(set(dups))[:MAX_NAMED])}. Choose a name field with one "
                       "value per ROI (or none: the feature ids are used).")
    return rois


def _plan(table: SurveyTable, traits, crops, ground, base) -> Tuple[List[Job], List[Job]]:
    """(jobs that start at once, jobs that wait for the ground job): one per file whose traits
    are asked; crops go to ``<crops>/<date>/<kind>/`` (``<date>_row<n>`` for a repeated date)."""
    first, later = [], []
    seen_dates = set()
    for s in table.surveys:
        tag = s.date if s.date not in seen_dates else f"{s.date}_row{s.row}"
        seen_dates.add(s.date)
        for kind, path in s.files().items():
            if not set(KIND_TRAITS[kind]) & set(traits):
                continue
            job = Job(key=f"r{s.row}-{kind}", kind=kind, path=path, row=s.row, date=s.date,
                      crs=s.crs, bands=s.bands if kind == "orthomosaic" else None,
                      crops=os.path.join(crops, _safe(tag), kind) if crops else None, **base)
            (later if kind in ("dsm", "point_cloud") and ground else first).append(job)
    return first, later


def _execute(runner, first: List[Job], later: List[Job], local: bool, prog, say) -> List[JobResult]:
    """Run the jobs on ``runner``: ``first`` at once, ``later`` with the ground job's planes.
    Progress after every job; on cancellation or error, pending jobs are cancelled and a cancel
    file tells running ones to stop at their next block."""
    total = len(first) + len(later)
    say(f"{total} jobs on {runner.label}")
    cancel_dir = tempfile.mkdtemp(prefix="easyidp-season-")
    cancel_file = os.path.join(cancel_dir, "cancel")
    threads = max(1, (os.cpu_count() or 1) // runner.workers) if runner.workers and local else None
    for job in first + later:
        job.cancel_file, job.threads = cancel_file, threads   # local workers share the cores
    results: List[JobResult] = []
    pending = {runner.submit(run_job, j, j.key): j for j in first}
    try:
        while pending:
            done = wait_any(list(pending), prog.cancelled)
            prog.check()
            for f in done:
                job = pending.pop(f)
                res = _result(f, job)
                results.append(res)
                _report(res, say)
                if job.kind == "ground":
                    _start_later(res, later, pending, runner)
                prog.set(100.0 * len(results) / total)
    except BaseException:
        open(cancel_file, "w").close()
        for f in pending:
            f.cancel()
        raise
    finally:
        shutil.rmtree(cancel_dir, ignore_errors=True)
    return results


def _safe(tag: str) -> str:
    return tag.replace(":", "-")


def _result(future, job: Job) -> JobResult:
    """The job's result; an exception of the job (a bug, a worker lost too often) becomes its
    error, so the season goes on."""
    try:
        return future.result()
    except Cancelled:
        raise
    except Exception as exc:  # noqa: BLE001 (reported by row, never aborts the season)
        name = type(exc).__name__
        hint = " (its worker died repeatedly: out of memory?)" if name == "KilledWorker" else ""
        return JobResult(job.key, job.kind, job.row, job.date, job.path,
                         error=f"{name}: {exc}{hint}")


def _start_later(ground: JobResult, later: List[Job], pending: dict, runner) -> None:
    if ground.error:
        raise EasyIDPError(f"Ground raster {ground.path}: {ground.error}")
    for job in later:
        job.ground = ground.planes
        pending[runner.submit(run_job, job, job.key)] = job


def _report(res: JobResult, say) -> None:
    where = "ground raster" if res.kind == "ground" else f"row {res.row} ({res.date}) {res.kind}"
    if res.error:
        say(f"{where}: left out: {res.error}")
        return
    extra = "; ".join(res.notes)
    say(f"{where}: {len(res.values) or len([p for p in res.planes or [] if p])} ROIs in "
        f"{res.seconds:.1f} s on {res.worker}" + (f"; {extra}" if extra else ""))


def _long_rows(rois: ROISet, results: List[JobResult], problems: List[RowProblem],
               notes: List[str]):
    """The long rows; job errors become row problems, ROIs without values become notes."""
    rows, taken, dup = [], set(), 0
    for res in sorted(results, key=lambda r: (r.row, r.kind)):
        if res.error:
            if res.kind != "ground":
                problems.append(RowProblem(res.row, res.date, res.kind, res.error))
            continue
        if res.skipped:
            named = ", ".join(f"{k} ({v})" for k, v in list(res.skipped.items())[:MAX_NAMED])
            more = " …" if len(res.skipped) > MAX_NAMED else ""
            where = "ground raster" if res.kind == "ground" else f"row {res.row} ({res.date}) {res.kind}"
            notes.append(f"{where}: {len(res.skipped)} ROI(s) without values: {named}{more}")
        for i, values in res.values.items():
            name = rois[i].name
            for trait, v in values.items():
                if v is None or not math.isfinite(v):
                    continue
                key = (name, res.date, trait)
                if key in taken:
                    dup += 1
                    continue
                taken.add(key)
                rows.append((name, res.date, trait, float(v)))
    problems.sort(key=lambda p: (p.row, p.column))
    return rows, dup


def _trait_key(name: str):
    for k, prefix in enumerate(TRAIT_ORDER):
        if name.startswith(prefix):
            return (k, _percentile_of(name), name)
    return (len(TRAIT_ORDER), 0.0, name)


def _percentile_of(name: str) -> float:
    if "_p" in name:
        try:
            return float(name.rsplit("_p", 1)[1].replace("_", "."))
        except ValueError:
            pass
    return 0.0


def season_inputs(table: SurveyTable, ground: Optional[str] = None) -> List[str]:
    """The files a season reads (never written over): the table, the ground raster and every
    file and project of its surveys."""
    inputs = [p for p in [table.source, ground] if p]
    return inputs + [p for s in table.surveys for p in (*s.files().values(), s.project) if p]


def check_season_outputs(table: SurveyTable, outputs: Sequence[Optional[str]],
                         ground: Optional[str] = None, also: Sequence[Optional[str]] = ()) -> None:
    """Raise :class:`InputError` before any work when one of ``outputs`` (file paths; None
    skipped) is a file the season reads (:func:`season_inputs`, plus ``also``)."""
    inputs = season_inputs(table, ground) + [p for p in also if p]
    for path in outputs:
        if path:
            check_not_inputs(path, inputs)
