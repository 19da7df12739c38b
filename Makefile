# EasyIDP for QGIS: one entry point. Run as root on Debian 12 (apt is used when QGIS is missing).
#   make demo   build the demo data and run every tool on it through qgis_process
#   make test   all tests: core (two environments), real QGIS offscreen, qgis_process runs;
#               the comparisons with easyidp 2.0.4 run in its own environment (.venv-ref)
#   make bench  benchmarks against easyidp 2.0.4 and GDAL (minutes; not part of test)
#   make package  dist/easyidp_toolbox-<version>.zip for Install from ZIP and plugins.qgis.org
#               (STRICT=1: refuse metadata placeholders, for a release upload)
#   make screenshots  the README's pictures of the QGIS desktop (docs/desktop_*.png): a session
#               with the tools on the demo survey, in the real desktop under Xvfb
SHELL := /bin/bash
ROOT := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
PY_SYS := /usr/bin/python3
VENV := $(ROOT)/.venv
VENV_CORE := $(ROOT)/.venv-core
VENV_REF := $(ROOT)/.venv-ref
VENV_EXACT := $(ROOT)/.venv-exactextract
# The plugin folder must be named easyidp_toolbox: .plugins/easyidp_toolbox links to this tree.
PLUGINS := $(ROOT)/.plugins
export QT_QPA_PLATFORM := offscreen
export PROJ_DATA := /usr/share/proj
export PYTHONDONTWRITEBYTECODE := 1
DEMO_DIR ?= $(ROOT)/demo_output

.PHONY: env env-ref env-exactextract test test-core test-core-current test-qgis demo bench package screenshots clean

env: apt $(VENV)/.done $(VENV_CORE)/.done

# xvfb, xauth: the QGIS desktop in tests/qgis/test_install_from_zip.py, test_desktop.py and
# make screenshots (it refuses to start offscreen)
APT_PACKAGES := qgis python3-qgis qgis-providers gdal-bin python3-venv python3-pip xvfb xauth

# Debian packages: installed when any is missing (checked on every run; takes a moment).
.PHONY: apt
apt:
	@dpkg -s $(APT_PACKAGES) >/dev/null 2>&1 || { \
	    echo "== installing QGIS and Python tools from Debian (about a minute)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
	        --no-install-recommends $(APT_PACKAGES) >/dev/null; }

$(PLUGINS)/easyidp_toolbox:
	mkdir -p $(PLUGINS) && ln -sfn $(ROOT) $@

$(VENV)/.done: requirements/qgis.txt | apt $(PLUGINS)/easyidp_toolbox
	@echo "== creating $(VENV) (QGIS interpreter, numpy < 2)"
	@test -x $(VENV)/bin/python || $(PY_SYS) -m venv --system-site-packages $(VENV)
	$(VENV)/bin/pip install -q --disable-pip-version-check -r requirements/qgis.txt
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

test: env env-ref
	$(MAKE) --no-print-directory test-core test-core-current test-qgis

test-core:
	@echo "== core tests, QGIS environment (numpy 1.26)"
	cd $(ROOT) && $(VENV)/bin/python -m pytest -q -p no:pytest_qgis -p no:cacheprovider -m "not geopandas" tests/core

test-core-current:
	@echo "== core tests, current stack (numpy 2.x)"
	cd $(ROOT) && $(VENV_CORE)/bin/python -m pytest -q -p no:cacheprovider -m "not gdal" tests/core

test-qgis:
	@echo "== QGIS tests (real QGIS offscreen, and qgis_process runs)"
	cd $(ROOT) && $(VENV)/bin/python -m pytest -q -p no:cacheprovider --qgis_disable_gui tests/qgis

demo: env
	$(VENV)/bin/python -m easyidp_toolbox.scripts.demo $(DEMO_DIR)

bench: env env-ref env-exactextract
	$(VENV)/bin/python -m easyidp_toolbox.bench.run_all

screenshots: env
	$(VENV)/bin/python -m easyidp_toolbox.scripts.qgis_desktop --screenshots $(ROOT)/docs

package: env
	$(VENV)/bin/python -m easyidp_toolbox.scripts.package --output $(ROOT)/dist $(if $(STRICT),--strict)

clean:
	rm -rf $(VENV) $(VENV_CORE) $(VENV_REF) $(VENV_EXACT) $(PLUGINS) $(DEMO_DIR) $(ROOT)/dist
