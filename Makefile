# EasyIDP for QGIS: one entry point. Run as root on Debian 12 or 13 (apt is used when QGIS is missing),
# except make check, make realdata and make changelog, which need only Python 3 with venv.
#   make check  lint (ruff) and the unit tests, in .venv-check (packages from the registry): no
#               root, no QGIS, no real test data, no easyidp 2.0.4; the first thing make test runs
#   make realdata  the real test data from its public sources at pinned commits, each file checked
#               (REALDATA_FROM=DIR: from a local folder; REALDATA_MIRROR=URL: from a mirror)
#   make changelog  metadata.txt's version and changelog from core/__init__.py and CHANGELOG.md
#   make demo   build the demo data and run every tool on it through qgis_process (and compare
#               with easyidp 2.0.4 in its own environment, .venv-ref, built when missing)
#   make test   all tests: core (two environments), real QGIS offscreen, qgis_process runs and the
#               desktop, on this machine's QGIS and on the other QGIS of the matrix (Debian 12's
#               3.22, 13's 3.40, sid's 3.44), each in a cached Debian root (.ci/debian_root.sh)
#   make bench  benchmarks against easyidp 2.0.4 and GDAL (minutes; not part of test)
#   make package  dist/easyidp_toolbox-<version>.zip for Install from ZIP and plugins.qgis.org
#               (STRICT=1: refuse metadata placeholders, for a release upload)
#   make docs   the documentation site (docs/, mkdocs.yml) into site/, warnings as errors
#   make screenshots  the README's pictures of the QGIS desktop (docs/desktop_*.png): a session
#               with the tools on the demo survey, in the real desktop under Xvfb
SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
PY_SYS := /usr/bin/python3
VENV := $(ROOT)/.venv
VENV_CORE := $(ROOT)/.venv-core
VENV_REF := $(ROOT)/.venv-ref
VENV_EXACT := $(ROOT)/.venv-exactextract
VENV_OTY := $(ROOT)/.venv-orthority
VENV_CHECK := $(ROOT)/.venv-check
# where the real test data is (tests/*/conftest.py look there too)
REALDATA ?= $(or $(EASYIDP_REALDATA),$(abspath $(ROOT)/../shared/realdata))
# the files ruff format keeps (the rest of the tree keeps its hand layout; pyproject.toml)
FORMAT_CHECKED := core/safe_xml.py scripts/changelog.py scripts/realdata.py tests/support/markers.py \
    tests/core/test_wheel.py tests/core/test_realdata.py tests/core/test_changelog.py \
    tests/core/test_safe_xml.py
# The plugin folder must be named easyidp_toolbox: .plugins/easyidp_toolbox links to this tree.
PLUGINS := $(ROOT)/.plugins
export QT_QPA_PLATFORM := offscreen
export PROJ_DATA := /usr/share/proj
export PYTHONDONTWRITEBYTECODE := 1
# where tests, the demo and the benchmarks find easyidp 2.0.4 (scripts/reference.py)
export EASYIDP_REF_PYTHON = $(VENV_REF)/bin/python
# where tests and the benchmarks find Orthority's command line (scripts: make env-orthority)
export EASYIDP_ORTHORITY = $(VENV_OTY)/bin/oty
DEMO_DIR ?= $(ROOT)/demo_output

# The QGIS matrix: one Debian release per QGIS. This machine's is tested here, the others in roots.
SUITES := bookworm trixie sid
CODENAME := $(shell . /etc/os-release 2>/dev/null && echo $$VERSION_CODENAME)
HOST_SUITE := $(if $(filter bookworm trixie,$(CODENAME)),$(CODENAME),sid)
OTHER_SUITES := $(filter-out $(HOST_SUITE),$(SUITES))

.PHONY: check realdata changelog env env-qgis env-ref env-exactextract env-orthority test test-core test-core-current test-qgis test-roots test-root apt-packages demo \
        bench package screenshots clean

env: env-qgis $(VENV_CORE)/.done
env-qgis: apt $(VENV)/.done

# xvfb, xauth: the QGIS desktop in tests/qgis/test_install_from_zip.py, test_desktop.py and
# make screenshots (it refuses to start offscreen)
APT_PACKAGES := qgis python3-qgis qgis-providers gdal-bin python3-venv python3-pip xvfb xauth
# chromium: the documentation site opened in a real browser (tests/qgis/test_docs_site.py)
APT_PACKAGES += chromium
# fonts-noto-cjk: the Chinese and Japanese tool names drawn and measured in the desktop
# (tests/qgis/test_desktop.py: no name is elided in the toolbox)
APT_PACKAGES += fonts-noto-cjk
# libimage-exiftool-perl: exiftool reads the FLIR photos the thermal tests write
APT_PACKAGES += libimage-exiftool-perl

# Debian packages: installed when any is missing (checked on every run; takes a moment).
.PHONY: apt
apt:
	@dpkg -s $(APT_PACKAGES) >/dev/null 2>&1 || { \
	    echo "== installing QGIS and Python tools from Debian (about a minute)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
	        --no-install-recommends $(APT_PACKAGES) >/dev/null; }

$(PLUGINS)/easyidp_toolbox:
	mkdir -p $(PLUGINS) && ln -sfn $(ROOT) $@

$(VENV)/.done: requirements/qgis.txt requirements/system_pins.py | apt $(PLUGINS)/easyidp_toolbox
	@echo "== creating $(VENV) (QGIS interpreter $$($(PY_SYS) -V), Debian $(HOST_SUITE))"
	@test -x $(VENV)/bin/python || $(PY_SYS) -m venv --system-site-packages $(VENV)
	@# what Debian's QGIS ships is pinned to the installed version: pip never replaces it
	$(PY_SYS) requirements/system_pins.py requirements/qgis.txt > $(VENV)/system-pins.txt
	$(VENV)/bin/pip install -q --disable-pip-version-check --prefer-binary \
	    -c $(VENV)/system-pins.txt -r requirements/qgis.txt
	@# pyopf on Debian 12 (Python 3.11): without its Pillow >= 10 metadata pin (requirements/qgis.txt)
	if $(VENV)/bin/python -c 'import sys; sys.exit(sys.version_info >= (3, 12))'; then \
	    $(VENV)/bin/pip install -q --disable-pip-version-check --no-deps \
	        "$$(grep -o '^pyopf==[0-9.]*' requirements/qgis.txt)"; fi
	echo $(PLUGINS) > $$($(VENV)/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/easyidp_toolbox.pth
	touch $@

$(VENV_CORE)/.done: requirements/current.txt | apt $(PLUGINS)/easyidp_toolbox
	@echo "== creating $(VENV_CORE) (current stack: numpy 2.x, newest releases, no QGIS)"
	@test -x $(VENV_CORE)/bin/python || $(PY_SYS) -m venv $(VENV_CORE)
	$(VENV_CORE)/bin/pip install -q --disable-pip-version-check -U -r requirements/current.txt
	echo $(PLUGINS) > $$($(VENV_CORE)/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/easyidp_toolbox.pth
	touch $@

env-ref: apt $(VENV_REF)/.done

$(VENV_REF)/.done: requirements/reference.txt | apt
	@echo "== creating $(VENV_REF) (easyidp 2.0.4, the reference; never imported by the plugin)"
	@test -x $(VENV_REF)/bin/python || $(PY_SYS) -m venv $(VENV_REF)
	$(VENV_REF)/bin/pip install -q --disable-pip-version-check -r requirements/reference.txt
	touch $@

# exactextract 0.3.0, the peer of ROI heights from DSM in bench/bench_heights.py: Debian's Python
# with its GDAL bindings (exactextract reads the DSM and the plots through them)
env-exactextract: apt $(VENV_EXACT)/.done

$(VENV_EXACT)/.done: requirements/exactextract.txt | apt
	@echo "== creating $(VENV_EXACT) (exactextract, for the benchmarks only)"
	@test -x $(VENV_EXACT)/bin/python || $(PY_SYS) -m venv --system-site-packages $(VENV_EXACT)
	$(VENV_EXACT)/bin/pip install -q --disable-pip-version-check -r requirements/exactextract.txt
	touch $@

# Orthority 0.7.0, the peer of the photo-folder cameras (tests) and of Orthorectify ROIs (bench):
# its own venv from the registry; tests and benchmarks find its oty through EASYIDP_ORTHORITY
env-orthority: apt $(VENV_OTY)/.done

$(VENV_OTY)/.done: requirements/orthority.txt | apt
	@echo "== creating $(VENV_OTY) (Orthority 0.7.0, a peer; never imported by the plugin)"
	@test -x $(VENV_OTY)/bin/python || $(PY_SYS) -m venv $(VENV_OTY)
	$(VENV_OTY)/bin/pip install -q --disable-pip-version-check --prefer-binary -r requirements/orthority.txt
	touch $@

# make check: a venv of Python 3 (python3-venv on Debian) with the current stack and ruff
$(VENV_CHECK)/.done: requirements/current.txt requirements/check.txt | $(PLUGINS)/easyidp_toolbox
	@echo "== creating $(VENV_CHECK) (ruff and the current stack, from the registry; no QGIS)"
	@test -x $(VENV_CHECK)/bin/python || $(PY_SYS) -m venv $(VENV_CHECK)
	$(VENV_CHECK)/bin/pip install -q --disable-pip-version-check --prefer-binary -r requirements/check.txt
	echo $(PLUGINS) > $$($(VENV_CHECK)/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/easyidp_toolbox.pth
	touch $@

check: $(VENV_CHECK)/.done
	@echo "== lint (ruff; the rules in pyproject.toml)"
	cd $(ROOT) && $(VENV_CHECK)/bin/ruff check --no-cache . && $(VENV_CHECK)/bin/ruff format --no-cache --check $(FORMAT_CHECKED)
	@echo "== unit tests (no QGIS, real data or easyidp 2.0.4)"
	cd $(ROOT) && EASYIDP_REALDATA=$(ROOT)/.no-realdata EASYIDP_REF_PYTHON=$(ROOT)/.no-reference \
	    $(VENV_CHECK)/bin/python -m pytest -q -p no:cacheprovider -m "unit and not gdal" tests/core

realdata:
	$(PY_SYS) $(ROOT)/scripts/realdata.py --to $(REALDATA) $(if $(REALDATA_FROM),--from $(REALDATA_FROM)) \
	    $(if $(REALDATA_MIRROR),--mirror $(REALDATA_MIRROR))

changelog:
	$(PY_SYS) $(ROOT)/scripts/changelog.py

test: check env env-ref env-orthority
	$(MAKE) --no-print-directory test-core test-core-current test-qgis test-roots

# The other QGIS of the matrix, each in a Debian root built once and cached (.ci/debian_root.sh,
# under /var/cache/easyidp-roots): the core tests on that root's Python and numpy, the QGIS suite
# (qgis_process runs and the desktop under Xvfb) and, in Debian 13's, make demo as a first command.
test-roots:
	@for s in $(OTHER_SUITES); do bash $(ROOT)/.ci/debian_root.sh $$s || exit 1; done
	@for s in $(OTHER_SUITES); do echo "== Debian $$s root: $$(bash $(ROOT)/.ci/debian_root.sh $$s run \
	    'qgis_process.bin --version 2>/dev/null | head -1')"; \
	    bash $(ROOT)/.ci/debian_root.sh $$s run "make --no-print-directory test-root SUITE=$$s" || exit 1; done

# Inside a root (SUITE=trixie|sid|bookworm): a venv of its own beside the host's.
ROOT_VARS = VENV=$(ROOT)/.venv-$(SUITE) VENV_REF=$(ROOT)/.venv-ref-$(SUITE) VENV_OTY=$(ROOT)/.venv-orthority-$(SUITE) DEMO_DIR=$(ROOT)/demo_output-$(SUITE)
test-root:
	$(if $(filter trixie,$(SUITE)),rm -rf $(ROOT)/demo_output-$(SUITE) && $(MAKE) --no-print-directory $(ROOT_VARS) demo)
	$(MAKE) --no-print-directory $(ROOT_VARS) env-qgis env-ref env-orthority test-core test-qgis

apt-packages:
	@echo $(APT_PACKAGES)

test-core:
	@echo "== core tests, QGIS environment ($(VENV): numpy $$($(VENV)/bin/python -c "import numpy; print(numpy.__version__)"))"
	cd $(ROOT) && $(VENV)/bin/python -m pytest -q -p no:pytest_qgis -p no:cacheprovider -m "not geopandas" tests/core

test-core-current:
	@echo "== core tests, current stack (numpy 2.x)"
	cd $(ROOT) && $(VENV_CORE)/bin/python -m pytest -q -p no:cacheprovider -m "not gdal" tests/core

test-qgis:
	@echo "== QGIS tests (real QGIS offscreen, and qgis_process runs)"
	cd $(ROOT) && $(VENV)/bin/python -m pytest -q -p no:cacheprovider --qgis_disable_gui tests/qgis

demo: env-qgis env-ref
	$(VENV)/bin/python -m easyidp_toolbox.scripts.demo $(DEMO_DIR)

bench: env env-ref env-exactextract env-orthority
	$(VENV)/bin/python -m easyidp_toolbox.bench.run_all

# The documentation site: MkDocs in a venv of its own (.venv-docs, requirements/docs.txt), strict:
# a warning (broken link, missing page or anchor, unreadable docstring) fails the build. make test
# builds it first: tests/qgis/test_docs_site.py opens the built pages in Chromium.
VENV_DOCS := $(ROOT)/.venv-docs
.PHONY: docs
docs: $(VENV_DOCS)/.done | $(PLUGINS)/easyidp_toolbox
	cd $(ROOT) && NO_MKDOCS_2_WARNING=1 $(VENV_DOCS)/bin/mkdocs build --strict --quiet --site-dir $(ROOT)/site

$(VENV_DOCS)/.done: requirements/docs.txt | apt
	@echo "== creating $(VENV_DOCS) (MkDocs, for make docs)"
	@test -x $(VENV_DOCS)/bin/python || $(PY_SYS) -m venv $(VENV_DOCS)
	$(VENV_DOCS)/bin/pip install -q --disable-pip-version-check -r requirements/docs.txt
	touch $@

test: docs

screenshots: env
	$(VENV)/bin/python -m easyidp_toolbox.scripts.qgis_desktop --screenshots $(ROOT)/docs

package: env
	$(VENV)/bin/python -m easyidp_toolbox.scripts.package --output $(ROOT)/dist $(if $(STRICT),--strict)

clean:
	rm -rf $(VENV) $(VENV_CORE) $(VENV_REF) $(VENV_CHECK) $(VENV_EXACT) $(VENV_OTY) $(VENV_DOCS) \
	    $(PLUGINS) $(DEMO_DIR) $(ROOT)/dist $(ROOT)/site \
	    $(foreach s,$(SUITES),$(ROOT)/.venv-$(s) $(ROOT)/.venv-ref-$(s) $(ROOT)/.venv-orthority-$(s) \
	                          $(ROOT)/demo_output-$(s))
