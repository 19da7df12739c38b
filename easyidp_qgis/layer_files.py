"""The file behind a layer or an output, found one way: ``QgsProviderRegistry.decodeUri``."""
from qgis.core import QgsProviderRegistry


def uri_file(source: str, provider: str = "ogr") -> str:
    """The file path of a layer source of ``provider`` ('x.gpkg|layername=a', a delimited-text
    'file:///…?delimiter=,' URI, a plain path), or of a Processing output URI
    ('ogr:dbname=…'); '' when there is none (a memory layer)."""
    s = str(source or "")
    if s.startswith("ogr:"):            # a Processing output: 'ogr:dbname='x.gpkg' table=…'
        for part in s[4:].split():
            if part.startswith("dbname="):
                return part[7:].strip("'\"")
        return ""
    return QgsProviderRegistry.instance().decodeUri(provider, s).get("path") or ""


def layer_file(layer) -> str:
    """The file behind a map layer ('' when there is none)."""
    return uri_file(layer.source(), layer.providerType()) if layer is not None else ""
