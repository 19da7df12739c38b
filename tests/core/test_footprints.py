"""Camera centres and footprints on a constant height and on a callable surface."""
import numpy as np
import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.projection import FootprintStatus, camera_footprints


@pytest.fixture(scope="module")
def wheat(realdata):
    return open_reconstruction(realdata / "easyidp" / "metashape" / "wheat_tanashi.psx")


@pytest.fixture(scope="module")
def pix4d(realdata):
    return open_reconstruction(realdata / "easyidp" / "pix4d_origin", source_crs="EPSG:32654")


def test_footprints_on_constant_height_project_back_onto_the_border(wheat):
    ground = float(np.mean([m.reference[2] for m in wheat.markers]))      # ellipsoidal, m
    fps = camera_footprints(wheat, ground, output_crs="EPSG:32654", cameras=wheat.aligned_cameras[:6],
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


def test_footprints_on_a_dsm_with_nodata(pix4d, tmp_path):
    """A sloped DSM with a hole (nodata) under part of the scene: rings on the DSM where it
    has data (checked against the DSM's own bilinear heights), the plane under the camera
    elsewhere (``complete`` False)."""
    from easyidp_toolbox.tests.support.synthetic import write_tif
    from easyidp_toolbox.core.raster import DSM
    _, c = pix4d.camera_centres()
    x0, y1 = c[:, 0].min() - 150, c[:, 1].max() + 150
    w, h = int((c[:, 0].max() + 150 - x0) / 0.5), int((y1 - c[:, 1].min() + 150) / 0.5)
    x = x0 + (np.arange(w) + 0.5) * 0.5
    z = np.broadcast_to(96.0 + 0.1 * (x - 368109.0), (h, w)).astype(np.float32).copy()
    hole = 368112.0                       # under some footprints, beside others
    z[:, x > hole] = -9999
    dsm = DSM(write_tif(str(tmp_path / "dsm.tif"), z, origin=(x0, y1), pixel=0.5,
                        nodata=-9999, tile=256))

    def ground(px, py):                   # the DSM's surface where it has data (a plane)
        return 96.0 + 0.1 * (px - 368109.0)

    cams = pix4d.aligned_cameras[::40]
    fps = camera_footprints(pix4d, dsm, cameras=cams, per_edge=8)
    assert {fp.complete for fp in fps} == {True, False}
    for fp in fps:
        assert np.isfinite(fp.height_above_ground)
        # nodata under the camera: the height above the DSM where its photo sees the ground
        assert (fp.status in (FootprintStatus.GROUND_FROM_FOOTPRINT,
                              FootprintStatus.GROUND_FROM_OTHERS)) == (fp.centre[0] >= hole)
        assert bool(fp.message) == (fp.centre[0] >= hole)
        ring = fp.ring
        on = ring[:, 0] < hole - 1.0
        assert np.allclose(ring[on, 2], ground(ring[on, 0], ring[on, 1]), atol=1e-3)
        p = pix4d.project_points(ring, cameras=[fp.label])
        assert (np.abs(p.pixels[0] - np.clip(p.pixels[0], 0, [5472, 3648])) < 0.05).all()
        centre_ground = fp.centre[2] - fp.height_above_ground
        if fp.centre[0] < hole - 1.0:
            assert centre_ground == pytest.approx(ground(fp.centre[0], fp.centre[1]), abs=1e-5)  # float32
    # centre reported in the map CRS equals the calibrated centre + offset
    assert np.allclose(fps[0].centre, cams[0].C + pix4d.frame.offset)


def test_camera_centres_and_no_ground_error(wheat):
    labels, c = wheat.camera_centres("EPSG:4326")
    assert len(labels) == 138 and np.all((c[:, 0] > 139.5) & (c[:, 0] < 139.6))
    with pytest.raises(Exception, match="No camera is above the given ground"):
        camera_footprints(wheat, 10_000.0, cameras=wheat.aligned_cameras[:2])


def test_cameras_below_the_ground_get_no_footprint(realdata):
    """goya_test is in a local CRS with cameras at z of about -20 .. +20: with the ground at 0,
    those below it are reported and get no footprint, never a complete zero-size one."""
    from easyidp_toolbox.core.reconstruction import open_reconstruction
    recon = open_reconstruction(realdata / "easyidp/metashape/goya_test.psx")
    z = recon.from_model(np.array([c.C for c in recon.aligned_cameras]))[:, 2]
    ground = float(np.median(z))                      # half the cameras are below it
    fps = camera_footprints(recon, ground, per_edge=4)
    below = [f for f in fps if f.below_ground]
    assert 0 < len(below) < len(fps)
    assert all(f.ring is None and not f.complete and f.status is FootprintStatus.BELOW_GROUND
               and f.message == "the camera is at or below the ground: no footprint" for f in below)
    assert all(f.area > 0 for f in fps if f.ring is not None)         # never a zero-size ring
