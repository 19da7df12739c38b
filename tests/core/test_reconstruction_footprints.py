"""Camera centres and footprints on a constant height and on a callable surface."""
import numpy as np
import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.reconstruction import camera_footprints


@pytest.fixture(scope="module")
def wheat(realdata):
    return open_reconstruction(realdata / "easyidp" / "metashape" / "wheat_tanashi.psx")


@pytest.fixture(scope="module")
def pix4d(realdata):
    return open_reconstruction(realdata / "easyidp" / "pix4d_origin", crs="EPSG:32654")


def test_footprints_on_constant_height_project_back_onto_the_border(wheat):
    ground = float(np.mean([m.reference[2] for m in wheat.markers]))      # ellipsoidal, m
    fps = camera_footprints(wheat, ground, crs="EPSG:32654", cameras=wheat.aligned_cameras[:6],
                            per_edge=6)
    assert len(fps) == 6
    for fp in fps:
        assert fp.complete and fp.ring.shape == (24, 3)
        assert np.allclose(fp.ring[:, 2], ground, atol=2e-3)
        assert 25 < fp.height_above_ground < 40                            # flown at 30 m
        assert fp.view_angle < 20
        assert 300 < fp.area < 2000                                         # m²
        # ring vertices project back onto the image border
        p = wheat.project_points(fp.ring, "EPSG:32654", cameras=[fp.label])
        uv = p.pixels[0]
        s = wheat.sensors["0"]
        d_border = np.minimum.reduce([np.abs(uv[:, 0]), np.abs(uv[:, 0] - s.width),
                                      np.abs(uv[:, 1]), np.abs(uv[:, 1] - s.height)])
        assert d_border.max() < 0.05
    # area equals the shoelace of the UTM ring to within UTM scale (~0.1 %)
    r = fps[0].ring
    shoelace = 0.5 * abs(np.dot(r[:, 0], np.roll(r[:, 1], -1)) - np.dot(r[:, 1], np.roll(r[:, 0], -1)))
    assert fps[0].area == pytest.approx(shoelace, rel=3e-3)


def test_footprints_on_a_surface_callable_with_nodata(pix4d):
    """A sloped surface with a hole (NaN) under part of the scene."""
    def ground(x, y):
        z = 96.0 + 0.1 * (x - 368109.0)
        return np.where((x > 368150.0), np.nan, z)

    cams = pix4d.aligned_cameras[::40]
    fps = camera_footprints(pix4d, ground, cameras=cams, per_edge=8)
    for fp in fps:
        assert np.isfinite(fp.height_above_ground)
        hit = fp.ring
        assert np.allclose(hit[:, 2], ground(hit[:, 0], hit[:, 1]), atol=2e-3)
        p = pix4d.project_points(hit, cameras=[fp.label])
        assert (np.abs(p.pixels[0] - np.clip(p.pixels[0], 0, [5472, 3648])) < 0.05).all()
    # centre reported in the map CRS equals the calibrated centre + offset
    assert np.allclose(fps[0].centre, cams[0].C + pix4d.frame.offset)


def test_camera_centres_and_no_ground_error(wheat):
    labels, c = wheat.camera_centres("EPSG:4326")
    assert len(labels) == 138 and np.all((c[:, 0] > 139.5) & (c[:, 0] < 139.6))
    with pytest.raises(Exception, match="No camera is above the given ground"):
        camera_footprints(wheat, 10_000.0, cameras=wheat.aligned_cameras[:2])
