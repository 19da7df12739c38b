"""XML documents read without a DTD: the engine's one XML parser.

Project files (Metashape ``doc.xml`` and camera exports, Pix4D ``.p4d``) and GDAL's metadata tag
in a GeoTIFF come from the user's disk and may have been crafted. :func:`parse_xml` reads them
with the standard library's expat parser and refuses any document that has a document type
declaration (``<!DOCTYPE …>``): without one no entity can be declared, so only the five predefined
entities and character references expand. Nothing can grow ("billion laughs", quadratic blowup)
and nothing outside the document is read (external entities, external DTDs). None of the files
read here has a DTD. The tree is ElementTree's (``Element``), built by its ``TreeBuilder``.
"""

import xml.parsers.expat
from typing import Union

# Only the tree classes are used from ElementTree, not its parser: documents are parsed by the
# expat parser below, which refuses a DTD (and so every entity declaration).
from xml.etree.ElementTree import Element, TreeBuilder  # nosec B405 -- tree classes only

__all__ = ["Element", "XMLError", "parse_xml"]


class XMLError(ValueError):
    """Not a well-formed XML document, or one with a DTD (refused)."""


def _refuse_dtd(*_args) -> None:
    raise XMLError(
        "it has a document type declaration (<!DOCTYPE>), which project files never "
        "have; it is refused so that no entity can expand"
    )


def parse_xml(data: Union[bytes, str]) -> Element:
    """The root element of the document ``data``. Raises :class:`XMLError` (a ValueError)
    when it is not well-formed XML or has a DTD. Namespaced names are ElementTree's
    ``{uri}tag``."""
    builder = TreeBuilder()
    parser = xml.parsers.expat.ParserCreate(namespace_separator="}")
    parser.buffer_text = True
    parser.StartDoctypeDeclHandler = _refuse_dtd
    parser.EntityDeclHandler = _refuse_dtd
    parser.UnparsedEntityDeclHandler = _refuse_dtd
    parser.ExternalEntityRefHandler = _refuse_dtd

    def name(raw: str) -> str:
        return "{" + raw if "}" in raw else raw

    parser.StartElementHandler = lambda tag, attrs: builder.start(
        name(tag), {name(k): v for k, v in attrs.items()}
    )
    parser.EndElementHandler = lambda tag: builder.end(name(tag))
    parser.CharacterDataHandler = builder.data
    try:
        parser.Parse(data, True)
    except (xml.parsers.expat.ExpatError, LookupError) as exc:  # LookupError: unknown encoding
        raise XMLError(str(exc)) from None
    return builder.close()
