"""Parameters several tools share: optional numbers and outputs, a Z range, percentiles; the
marker of labels kept in tables (:func:`translatable`)."""
import math
import re

from qgis.core import QgsProcessingException, QgsProcessingParameterNumber

from .compat import ProcessingNumberParameterType, ProcessingParameterFlag


def translatable(text: str) -> str:
    """Mark a string kept in a table (a choice label) for the translation catalogues; it is
    translated where it is shown, with ``tr``."""
    return text


def with_help(p, text: str):
    """``p`` with ``text`` as its help (the dialog's tooltip): the details that do not fit the
    one-line label (labels stay under about 60 characters, so a dialog shows them on one line)."""
    p.setHelp(text)
    return p


def optional_number(alg, parameters, name: str, context):
    """The value of an optional number parameter, or None when it is not set."""
    if parameters.get(name) in (None, ""):
        return None
    return alg.parameterAsDouble(parameters, name, context)


def optional_destination(alg, parameters, name: str, context):
    """The path of an optional file or folder output, or None when it was left empty."""
    if parameters.get(name) in (None, ""):
        return None
    return alg.parameterAsFileOutput(parameters, name, context) or None


def add_z_range_parameters(alg):
    """Advanced, optional Z_MIN and Z_MAX."""
    for name, label in ((alg.Z_MIN, alg.tr("Lowest Z to keep (cloud Z units; empty: no limit)")),
                        (alg.Z_MAX, alg.tr("Highest Z to keep (cloud Z units; empty: no limit)"))):
        p = QgsProcessingParameterNumber(name, label, ProcessingNumberParameterType.Double,
                                         optional=True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        alg.addParameter(p)


def z_range(alg, parameters, context):
    """(z_min, z_max) from Z_MIN / Z_MAX, None where not set."""
    z_min = optional_number(alg, parameters, alg.Z_MIN, context)
    z_max = optional_number(alg, parameters, alg.Z_MAX, context)
    if z_min is not None and z_max is not None and z_min > z_max:
        raise QgsProcessingException(f"Z range: the lowest Z to keep ({z_min:g}) is above the "
                                     f"highest ({z_max:g}).")
    return z_min, z_max


def parse_percentiles(alg, text: str, default=()):
    """'5, 50 95;99' → [5.0, 50.0, 95.0, 99.0] (order kept, repeats dropped); ``default`` when
    empty; QgsProcessingException naming the token for anything that is not 0–100."""
    out = []
    for token in re.split(r"[,;\s]+", (text or "").strip()):
        if not token:
            continue
        try:
            q = float(token)
        except ValueError:
            q = math.nan
        if not 0 <= q <= 100:
            raise QgsProcessingException(alg.tr(
                "Percentiles: '{token}' is not a number from 0 to 100. Give percentiles "
                "separated by commas, e.g. 5,50,95.").format(token=token))
        if q not in out:
            out.append(q)
    return out or list(default)
