"""The project CRS as photogrammetry software writes it (issue 24): Metashape's WKT1 with its
typos and dialects, resolved by core.crs.project_crs in one place for Metashape and Pix4D.

Checks: the EPSG code a WKT resolves to is compared with the code it must be (by construction
of the WKT); the CH1903+ chunk is checked end to end against pyproj's own geodesy (a truth by
construction, independent of our frame code)."""
import warnings

import numpy as np
import pytest
from pyproj import CRS, Transformer

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.crs import (project_crs, same_definition, transform_columns, transformer,
                                      wkt_top_authority)
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.projection import back_project
from easyidp_toolbox.core.roi.model import ROISet, roi_from_coordinates
from easyidp_toolbox.tests.support.project_crs import (CENTRE_LV95, LV95_METASHAPE,
                                                       LV95_NO_AUTHORITY, LV95_SHIFTED, H, W,
                                                       chunk_xml)

# ESRI dialect, misspelt "Centre" names: PROJ cannot use it, and it omits the rectified grid angle
LV95_ESRI = (
    'PROJCS["CH1903+_LV95",GEOGCS["GCS_CH1903+",DATUM["D_CH1903+",SPHEROID["Bessel_1841",'
    '6377397.155,299.1528128]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]],'
    'PROJECTION["Hotine_Oblique_Mercator_Azimuth_Centre"],PARAMETER["False_Easting",2600000.0],'
    'PARAMETER["False_Northing",1200000.0],PARAMETER["Scale_Factor",1.0],PARAMETER["Azimuth",'
    '90.0],PARAMETER["Longitude_Of_Centre",7.439583333333333],PARAMETER["Latitude_Of_Centre",'
    '46.95240555555556],UNIT["Meter",1.0]]')
# UTM zone 52N parameters under a top-level AUTHORITY of zone 51N
UTM52_LABELLED_51 = CRS.from_epsg(32652).to_wkt("WKT1_GDAL").replace(
    'AUTHORITY["EPSG","32652"]]', 'AUTHORITY["EPSG","32651"]]')
# a custom Transverse Mercator (no EPSG code) that PROJ can use
CUSTOM_TM = ('PROJCS["farm grid",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,'
             '298.257223563]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],PROJECTION['
             '"Transverse_Mercator"],PARAMETER["latitude_of_origin",0],PARAMETER["central_meridian"'
             ',121.3],PARAMETER["scale_factor",0.9999],PARAMETER["false_easting",250000],PARAMETER['
             '"false_northing",0],UNIT["metre",1]]')


def test_pyproj_alone_cannot_use_the_metashape_wkt():
    """The fault itself: PROJ reads the WKT but cannot transform it, and finds no code at 90 %."""
    crs = CRS.from_user_input(LV95_METASHAPE).source_crs
    assert crs.to_epsg(min_confidence=90) is None
    with pytest.raises(Exception):
        Transformer.from_crs(crs, crs.geodetic_crs, always_xy=True)


@pytest.mark.parametrize("wkt, code, says", [
    (LV95_METASHAPE, 2056, "its own AUTHORITY"),
    (LV95_NO_AUTHORITY, 2056, "confidence 25"),
    (LV95_ESRI, 2056, "the parameters agree"),
    (UTM52_LABELLED_51, 32652, "EPSG:32651 disagrees with its parameters"),
    (CRS.from_epsg(4326).to_wkt("WKT1_GDAL"), 4326, ""),
])
def test_resolution_order(wkt, code, says):
    crs, how = project_crs(wkt, "chunk")
    assert crs.to_epsg() == code
    assert says in how if says else how == ""


def test_top_level_authority_only():
    assert wkt_top_authority(LV95_METASHAPE) == ("EPSG", "2056")
    assert wkt_top_authority(LV95_NO_AUTHORITY) is None      # nested ones (datum, unit) ignored


def test_parameters_compared_by_value_not_name():
    custom = CRS.from_user_input(LV95_METASHAPE).source_crs
    assert same_definition(custom, CRS.from_epsg(2056))
    assert not same_definition(CRS.from_user_input(LV95_SHIFTED).source_crs, CRS.from_epsg(2056))
    assert not same_definition(CRS.from_epsg(32652), CRS.from_epsg(32651))
    assert not same_definition(CRS.from_epsg(2056), CRS.from_epsg(21781))   # LV03: same shape


def test_custom_crs_kept_when_proj_can_use_it():
    crs, how = project_crs(CUSTOM_TM, "chunk")
    assert crs.to_epsg() is None and crs.name == "farm grid" and "kept as written" in how
    e, n = Transformer.from_crs(4326, crs, always_xy=True).transform(121.3, 10.0)
    assert e == pytest.approx(250000.0)


def test_unusable_crs_asks_for_it_by_name():
    with pytest.raises(InputError) as e:
        project_crs(LV95_SHIFTED, "doc.xml, chunk <reference>")
    msg = str(e.value)
    assert "doc.xml" in msg and "'CH1903+ / LV95'" in msg and "EPSG code" in msg
    crs, how = project_crs(LV95_SHIFTED, "chunk", "EPSG:2056")
    assert crs.to_epsg() == 2056 and "using the one given" in how
    with pytest.raises(InputError, match="do not pass another project CRS"):
        project_crs(LV95_METASHAPE, "chunk", "EPSG:4326")
    with pytest.raises(InputError, match="EPSG code"):
        project_crs("PROJCS[garbage", "chunk")


# --- a Metashape chunk in CH1903+ / LV95, end to end ---------------------------------------------
def test_lv95_chunk_places_cameras_and_projects_like_pyproj(tmp_path):
    """Truth by construction: the camera centre was put in the chunk through pyproj's LV95 →
    Bessel geocentric; a ground point 10 m east and 20 m north of the nadir point, 100 m below
    the camera, must land 100 px right of and 200 px above the principal point (pinhole)."""
    path, _ = chunk_xml(tmp_path, LV95_METASHAPE)
    recon = open_reconstruction(path)
    assert recon.crs.to_epsg() == 2056
    assert any("its own AUTHORITY" in n for n in recon.notes)
    labels, centres = recon.camera_centres()            # failed with ProjError before
    assert labels == ["IMG_0001"]
    np.testing.assert_allclose(centres[0], CENTRE_LV95, atol=1e-3)
    ground = np.array([[CENTRE_LV95[0] + 10.0, CENTRE_LV95[1] + 20.0, CENTRE_LV95[2] - 100.0]])
    proj = recon.project_points(ground)
    uv = proj.pixels[0, 0]
    # LV95 is conformal with scale ~1 near Bern: 10 m at 100 m depth → 100 px (to 0.1 px)
    np.testing.assert_allclose(uv, [W / 2 + 100.0, H / 2 - 200.0], atol=0.1)
    up = recon.frame.up(np.array([recon.cameras[0].C]))
    assert up.shape == (1, 3) and np.isfinite(up).all()
    # back-projection (the traceback of the issue, at 10 %) with a constant ground height
    x0, y0 = CENTRE_LV95[0] - 5.0, CENTRE_LV95[1] - 5.0
    roi = roi_from_coordinates("plot", "Polygon", [[[x0, y0], [x0 + 10, y0], [x0 + 10, y0 + 10],
                                                    [x0, y0 + 10], [x0, y0]]])
    bp = back_project(ROISet([roi], "EPSG:2056"), recon, heights=CENTRE_LV95[2] - 100.0)
    assert len(bp) == 1
    ring = bp.rings_of(0)[0]
    assert ring[:, 0].min() == pytest.approx(W / 2 - 50, abs=0.2)
    assert ring[:, 0].max() == pytest.approx(W / 2 + 50, abs=0.2)


def test_lv95_chunk_that_proj_cannot_use_asks_for_the_crs(tmp_path):
    path, _ = chunk_xml(tmp_path, LV95_SHIFTED)
    with pytest.raises(InputError) as e:
        open_reconstruction(path)
    assert "cameras.xml" in str(e.value) and "CH1903+ / LV95" in str(e.value)
    recon = open_reconstruction(path, source_crs="EPSG:2056")
    np.testing.assert_allclose(recon.camera_centres()[1][0], CENTRE_LV95, atol=1e-3)


def test_pix4d_wkt_prj_resolved_the_same_way(tmp_path, realdata):
    """The Pix4D reader goes through the same resolution (one place): its *_wkt.prj in the
    Metashape dialect gives EPSG:2056 (coordinates meaningless here; only the CRS is read)."""
    import shutil
    src = realdata / "easyidp" / "pix4d_origin" / "1_initial" / "params"
    dst = tmp_path / "1_initial" / "params"
    shutil.copytree(src, dst)
    (dst / "pix4d.origin_wkt.prj").write_text(LV95_NO_AUTHORITY)
    recon = open_reconstruction(dst)
    assert recon.crs.to_epsg() == 2056
    assert any("EPSG:2056" in n for n in recon.notes)


def test_transform_columns_takes_one_point_without_numpy_warnings():
    """pyproj 3.7 (Debian 13) takes one-element arrays for a point and numpy ≥ 1.25 warns on the
    conversion; one point must give what the same point does in a longer array."""
    t = transformer(CRS.from_epsg(32654), CRS.from_epsg(4326))
    x, y = np.array([368000.0, 369000.0]), np.array([3955000.0, 3956000.0])
    both = transform_columns(t, x, y)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        one = transform_columns(t, x[:1], y[:1])
    assert [a.shape for a in one] == [(1,), (1,)]
    assert [a[0] for a in one] == [a[0] for a in both]
