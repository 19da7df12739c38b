"""Side by side with easyidp 2.0.4's raw → map homography (its own environment): truth points
inside plots, from their true pixels to the map, on the demo survey's crop relief. The truth is
the survey generator's (independent of both)."""
import numpy as np

from easyidp_toolbox.scripts.homography_comparison import compare, report


def test_ray_dsm_is_at_least_five_times_closer_than_the_homography(demo, capsys):
    result = compare(demo.folder)
    with capsys.disabled():
        print("\n" + report(result))
    for name, r in result.items():
        assert r["points"] > 100
        assert r["ours"].max() < 1e-3                          # 1 mm
        assert r["easyidp"].mean() >= 5 * r["ours"].mean()
        assert np.percentile(r["easyidp"], 95) > 0.02          # the crop relief shows
