"""The output policy of every tool, checked before any work (see README, "Files and safety"):
an input is never an output, two outputs are never one file, and a file that already exists is
replaced only when the user ticks OVERWRITE (folders are checked by the core, name by name),
and an output file is held by one run at a time."""
import os
from contextlib import contextmanager

from qgis.core import (QgsProcessingException, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterFile, QgsProcessingParameterFileDestination,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterMultipleLayers,
                       QgsProcessingParameterRasterDestination,
                       QgsProcessingParameterVectorDestination)

from .layer_files import uri_file


def _file_of(source: str, provider: str = "ogr") -> str:
    """The real path of the file behind a layer source or output URI ('' when none)."""
    s = uri_file(source, provider)
    return os.path.realpath(s) if s and os.path.isabs(s) else ""


def _inputs(alg, parameters, context):
    """(file, parameter description) of every input file or file-backed layer."""
    out = []
    for p in alg.parameterDefinitions():
        if p.isDestination() or p.name() not in parameters or parameters[p.name()] in (None, ""):
            continue
        files = []
        if isinstance(p, QgsProcessingParameterFile):
            files = [_file_of(alg.parameterAsFile(parameters, p.name(), context))]
        elif isinstance(p, QgsProcessingParameterMultipleLayers):
            files = [_file_of(lay.source(), lay.providerType())
                     for lay in alg.parameterAsLayerList(parameters, p.name(), context)]
        elif p.type() in ("source", "vector", "raster", "layer", "mesh", "pointcloud"):
            layer = alg.parameterAsLayer(parameters, p.name(), context)
            files = [_file_of(layer.source(), layer.providerType())] if layer is not None else []
        out += [(f, p.description()) for f in files if f]
    return out


def scratch_context(context):
    """A context to resolve output paths in: ``parameterAsOutputLayer`` queues the layer for
    loading on completion, and a queued 'memory:…' that no sink then fills fails to load (an
    error in the desktop after every run to a temporary layer)."""
    from qgis.core import QgsProcessingContext
    scratch = QgsProcessingContext()
    scratch.setProject(context.project())
    scratch.setExpressionContext(context.expressionContext())
    return scratch


def _outputs(alg, parameters, context):
    """(file, parameter description) of every file output (sinks to memory are skipped)."""
    context = scratch_context(context)
    out = []
    for p in alg.destinationParameterDefinitions():
        if isinstance(p, QgsProcessingParameterFolderDestination):
            continue                      # the core checks the names it writes into a folder
        if isinstance(p, (QgsProcessingParameterFeatureSink, QgsProcessingParameterVectorDestination)):
            dest = alg.parameterAsOutputLayer(parameters, p.name(), context)
        elif isinstance(p, (QgsProcessingParameterFileDestination, QgsProcessingParameterRasterDestination)):
            dest = alg.parameterAsFileOutput(parameters, p.name(), context)
        else:
            continue
        f = _file_of(dest)
        if f:
            out.append((f, p.description()))
    return out


def _leftover_why(alg, path: str) -> str:
    """Why the existing GeoPackage ``path`` is the leftover of an interrupted write and not a
    user's data ('' when it is a GeoPackage GDAL opens): empty (QGIS's writer had just created
    it), or a file GDAL cannot open (a kill while SQLite wrote its first pages, 64 KiB)."""
    if not path.lower().endswith(".gpkg") or not os.path.isfile(path):
        return ""
    size = os.path.getsize(path)
    if size == 0:
        return alg.tr("it is empty (0 bytes)")
    from osgeo import gdal
    with open(path, "rb") as fh:
        if not fh.read(16).startswith(b"SQLite format 3"):
            return ""                # not a database at all: someone else's file, kept
    gdal.PushErrorHandler("CPLQuietErrorHandler")
    try:                             # GDAL raises instead of returning None where another
        ds = gdal.OpenEx(path, gdal.OF_VECTOR | gdal.OF_READONLY,    # module in this process
                         allowed_drivers=["GPKG"])                  # called UseExceptions
    except RuntimeError:
        ds = None
    finally:
        gdal.PopErrorHandler()
    if ds is None:
        return alg.tr("GDAL cannot open it as a GeoPackage; {size:.0f} KiB").format(size=size / 1024)
    return ""


SIDE_FILES = ("-journal", "-wal", "-shm")
"""The files SQLite keeps next to a database while it writes (left behind by a kill)."""


def _remove_with_side_files(path: str) -> None:
    for p in [path] + [path + s for s in SIDE_FILES]:
        try:
            os.remove(p)
        except FileNotFoundError:
            pass


@contextmanager
def claim_outputs(alg, parameters, context, overwrite: bool, feedback=None):
    """Check the outputs before any work and hold them for the run.

    Raises QgsProcessingException when an output would replace an input, two outputs share a
    file, another run is writing the same output file, or (without ``overwrite``) an output
    file already exists. Each output file is locked (:func:`core.files.hold_lock`, a hidden
    ``.<name>.easyidp.lock`` beside it) for the whole run, then checked: of runs started
    together into one output, exactly one gets it. A GeoPackage left empty or unreadable by an
    interrupted run (see :func:`_leftover_why`) is removed with its SQLite side files and
    replaced, with a warning; SQLite side files left beside an output are removed too."""
    from ..core.files import LockHeld, file_lock_name, hold_lock
    inputs = _inputs(alg, parameters, context)
    seen = {}
    for f, what in _outputs(alg, parameters, context):
        for g, src in inputs:
            if f == g:
                raise QgsProcessingException(alg.tr(
                    "{output}: {path} is also the input '{input}'. Inputs are never overwritten: "
                    "choose another file.").format(output=what, path=f, input=src))
        if f in seen:
            raise QgsProcessingException(alg.tr(
                "'{a}' and '{b}' are both {path}: one would replace the other. Choose two "
                "files.").format(a=seen[f], b=what, path=f))
        seen[f] = what
    held = []
    try:
        for f, what in seen.items():
            try:                       # QGIS makes a missing folder of an output too
                os.makedirs(os.path.dirname(f), exist_ok=True)
            except OSError:
                check_output_location(alg, what, f)
            try:
                held.append(hold_lock(file_lock_name(f)))
            except LockHeld as exc:
                raise QgsProcessingException(alg.tr(
                    "{output}: another run ({holder}) is writing {path}; nothing was written. "
                    "Wait for it to finish, or choose another file.").format(
                        output=what, holder=exc.holder_text(), path=f)) from None
            except OSError as exc:
                check_output_location(alg, what, f)
                raise QgsProcessingException(alg.tr(
                    "{output}: {path} cannot be written: {why}. Choose a folder you can write "
                    "to.").format(output=what, path=f, why=exc.strerror or exc)) from None
            why = _leftover_why(alg, f)
            if why:
                _remove_with_side_files(f)
                if feedback is not None:
                    feedback.pushWarning(alg.tr(
                        "{output}: {path} was not a valid GeoPackage ({why}), the leftover of an "
                        "interrupted run; it is replaced.").format(output=what, path=f, why=why))
            elif os.path.exists(f) and not overwrite:
                raise QgsProcessingException(alg.tr(
                    "{output}: {path} already exists and nothing was written. Choose another file, "
                    "or tick 'Overwrite existing files' (advanced) to replace it.").format(
                        output=what, path=f))
            if f.lower().endswith(".gpkg") and (overwrite or not os.path.exists(f)):
                for side in SIDE_FILES:     # a killed writer's journal, not to be replayed
                    try:                    # into the new file
                        os.remove(f + side)
                    except FileNotFoundError:
                        pass
        yield
    finally:
        for lock in held:
            lock.release()


def check_output_location(alg, what: str, path: str) -> None:
    """Raise QgsProcessingException naming the output when its folder is a file, or it (or the
    nearest folder above it that exists, when it is missing) cannot be written to: a read-only
    file system or permissions (QGIS's own words for it are 'unable to open database')."""
    import errno
    folder = os.path.dirname(path)
    base = folder
    while base and not os.path.exists(base) and os.path.dirname(base) != base:
        base = os.path.dirname(base)
    if not os.path.isdir(base):
        raise QgsProcessingException(alg.tr(
            "{output}: {folder} is a file, not a folder. Choose another file.").format(
                output=what, folder=base))
    probe = os.path.join(base, f".easyidp-probe.{os.getpid()}")
    try:
        with open(probe, "wb"):
            pass
        os.remove(probe)
    except OSError as exc:
        why = (alg.tr("it is on a read-only file system") if exc.errno == errno.EROFS else
               alg.tr("you may not write there ({reason})").format(reason=exc.strerror or exc))
        raise QgsProcessingException(alg.tr(
            "{output}: {path} cannot be written: {why}. Choose a folder you can write "
            "to.").format(output=what, path=path, why=why)) from None
    if base != folder:
        raise QgsProcessingException(alg.tr(
            "{output}: the folder {folder} does not exist and cannot be created. Create it, or "
            "choose another file.").format(output=what, folder=folder))


def check_values(alg, parameters, context):
    """(ok, message) for numbers and choices, with the message QGIS's own check lacks: the
    parameter, the value and the range or the options. NaN and infinities are refused."""
    import math
    from qgis.core import QgsProcessingParameterEnum, QgsProcessingParameterNumber
    for p in alg.parameterDefinitions():
        value = parameters.get(p.name())
        if value is None or value == "" or p.isDestination():
            continue
        if isinstance(p, QgsProcessingParameterNumber):
            try:
                v = float(value)
            except (TypeError, ValueError):
                continue                       # an expression or a layer property: QGIS checks
            if not math.isfinite(v):
                return False, alg.tr("{name}: {value} is not a number; give a finite value.").format(
                    name=p.description(), value=value)
            if not p.minimum() <= v <= p.maximum():
                lo = "" if p.minimum() < -1e300 else f"{p.minimum():g}"
                hi = "" if p.maximum() > 1e300 else f"{p.maximum():g}"
                return False, alg.tr("{name}: {value:g} is outside the range {lo}–{hi}.").format(
                    name=p.description(), value=v, lo=lo or "−∞", hi=hi or "∞")
        elif isinstance(p, QgsProcessingParameterEnum) and not p.allowMultiple():
            try:
                k = int(value)
            except (TypeError, ValueError):
                continue
            if not 0 <= k < len(p.options()):
                opts = "; ".join(f"{i} = {o}" for i, o in enumerate(p.options()))
                return False, alg.tr("{name}: {value} is not one of the choices ({opts}).").format(
                    name=p.description(), value=k, opts=opts)
    return True, ""
