"""core.safe_xml: project XML read without a DTD (no entity can expand, nothing outside the
document is read), and otherwise the same tree as the standard library's parser.

Truth kind: xml.etree.ElementTree's own parser (the reference implementation) on documents
without a DTD; for the refusals, documents that it would expand.
"""

import xml.etree.ElementTree as ET  # nosec B405 -- the reference parser, in a test

import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.safe_xml import XMLError, parse_xml

LAUGHS = (
    b'<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol "lol">'
    b'<!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">'
    b'<!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">]>'
    b"<document><chunk>&lol3;</chunk></document>"
)
EXTERNAL = b'<!DOCTYPE d [<!ENTITY e SYSTEM "file:///etc/hostname">]><document>&e;</document>'
EXTERNAL_DTD = b'<!DOCTYPE document SYSTEM "http://127.0.0.1:9/x.dtd"><document/>'
PLAIN = (
    b'<?xml version="1.0" encoding="UTF-8"?>\n<document version="1.2.0">\n'
    b'  <chunk label="Chunk 1" enabled="true"><sensors next_id="1">'
    b'<sensor id="0" label="FC7203 (4.49mm)" type="frame">text &amp; &#233;</sensor>'
    b"</sensors>tail</chunk>\n"
    b'  <m:meta xmlns:m="urn:example:meta" m:key="v"><!-- a comment --><?pi data?>x</m:meta>\n'
    b"</document>"
)


def _same(a, b):
    assert (a.tag, a.attrib, a.text, a.tail) == (b.tag, b.attrib, b.text, b.tail)
    assert len(a) == len(b)
    for x, y in zip(a, b):
        _same(x, y)


def test_a_document_without_dtd_gives_elementtrees_tree():
    _same(parse_xml(PLAIN), ET.fromstring(PLAIN))
    text = PLAIN.decode("utf-8")
    _same(parse_xml(text.split("\n", 1)[1]), ET.fromstring(text.split("\n", 1)[1]))
    latin = '<?xml version="1.0" encoding="ISO-8859-1"?><a b="\xe9">\xe9</a>'.encode("latin-1")
    _same(parse_xml(latin), ET.fromstring(latin))


def test_the_standard_parser_would_expand_what_is_refused():
    assert len(ET.fromstring(LAUGHS).find("chunk").text) == 300  # what is refused below


@pytest.mark.parametrize("doc", [LAUGHS, EXTERNAL, EXTERNAL_DTD], ids=["laughs", "entity", "dtd"])
def test_a_dtd_is_refused(doc):
    with pytest.raises(XMLError, match="document type declaration"):
        parse_xml(doc)


@pytest.mark.parametrize("doc", [b"", b"<a><b></a>", b"<a>&undefined;</a>", b"\x00\x01"])
def test_bad_documents_are_xml_errors(doc):
    with pytest.raises(XMLError):
        parse_xml(doc)


def test_a_metashape_cameras_file_with_a_dtd_names_the_file(tmp_path):
    path = tmp_path / "cameras.xml"
    path.write_bytes(LAUGHS)
    with pytest.raises(InputError) as err:
        open_reconstruction(path)
    assert str(path) in str(err.value) and "document type declaration" in str(err.value)
