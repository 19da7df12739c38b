"""A small demo season for the season tests (6 plots, 20 m × 12 m, 4 dates), generated once."""
import os
from pathlib import Path

from easyidp_toolbox.core.demo.field import FieldLayout
from easyidp_toolbox.core.demo.season import make_demo_season

SMALL_FIELD = FieldLayout(origin=(319800.0, 3956050.0), size=(20.0, 12.0), rows=2, cols=3,
                          plot_size=(4.0, 2.5), first_plot=(4.0, 3.5), pitch=(6.5, 5.0),
                          ground=(95.0, 0.02, 0.01), nodata_cols=40, epsg=32654)


def small_season(folder: Path, dates: int = 4):
    """The small season in ``folder`` (reused when complete)."""
    season = make_demo_season(str(folder), dates=dates, seed=0, layout=SMALL_FIELD)
    assert os.path.isfile(season.truth)
    return season
