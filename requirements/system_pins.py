"""Print pip constraints that pin what Debian's QGIS ships to the installed versions.

    python3 requirements/system_pins.py requirements/qgis.txt > pins.txt

numpy, GDAL, pyproj, PyQt, scipy, matplotlib and Pillow come with QGIS: pip must never replace
them, except a package the requirements file pins for this Python itself (numpy 1.26 on Debian 12).
Run with the interpreter QGIS uses. Markers are read with pip's own ``packaging``.
"""
import importlib.metadata as metadata
import sys

from pip._vendor.packaging.requirements import Requirement

SHIPPED = ("numpy", "GDAL", "pyproj", "PyQt5", "PyQt6", "scipy", "matplotlib", "pillow")


def pinned_here(path):
    """Names the requirements file pins (==) for this interpreter, lower case."""
    names = set()
    for line in open(path, encoding="utf-8"):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        req = Requirement(line)
        if (req.marker is None or req.marker.evaluate()) and any(s.operator == "==" for s in req.specifier):
            names.add(req.name.lower())
    return names


def main(path):
    own = pinned_here(path)
    for name in SHIPPED:
        if name.lower() in own:
            continue
        try:
            print(f"{name}=={metadata.version(name)}")
        except metadata.PackageNotFoundError:
            pass


if __name__ == "__main__":
    main(sys.argv[1])
