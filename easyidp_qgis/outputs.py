"""The output policy of every tool, checked before any work (see README, "Files and safety"):
an input is never an output, two outputs are never one file, and a file that already exists is
replaced only when the user ticks OVERWRITE (folders are checked by the core, name by name)."""
import os

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


def check_outputs(alg, parameters, context, overwrite: bool) -> None:
    """Raise QgsProcessingException before any work when an output would replace an input,
    two outputs share a file, or (without ``overwrite``) an output file already exists."""
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
        if os.path.exists(f) and not overwrite:
            raise QgsProcessingException(alg.tr(
                "{output}: {path} already exists and nothing was written. Choose another file, "
                "or tick 'Overwrite existing files' (advanced) to replace it.").format(
                    output=what, path=f))


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
