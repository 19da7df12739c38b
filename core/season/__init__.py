"""A season of surveys: traits per ROI per date, on local processes or a Dask cluster.

>>> from easyidp_toolbox.core.roi import read_geojson
>>> from easyidp_toolbox.core.season import run_season, write_long_csv, plot_growth_curves
>>> result = run_season("surveys.csv", read_geojson("plots.geojson", name_field="plot_id"),
...                     ground="bare_soil_dsm.tif", workers=2)
>>> write_long_csv(result, "traits.csv"); plot_growth_curves(result, "curves.png")

* :mod:`.series` reads the table of surveys (date, orthomosaic, dsm, point_cloud, project);
* :mod:`.jobs` computes one file's traits for every ROI in one pass (:mod:`.traits`,
  :mod:`.ground`);
* :mod:`.executors` runs the jobs on a process pool or Dask; :mod:`.season` gathers them;
* :mod:`.outputs` and :mod:`.curves` write the tables, the wide layer and the growth curves.
"""
from .curves import main_trait, plot_growth_curves
from .outputs import write_long_csv, write_season_geopackage
from .season import SeasonResult, check_season_outputs, run_season, season_inputs
from .series import RowProblem, Survey, SurveyTable, read_survey_table, surveys_from_rows
from .traits import DEFAULT_PERCENTILES, TRAIT_GROUPS

__all__ = ["run_season", "SeasonResult", "read_survey_table", "surveys_from_rows", "Survey",
           "SurveyTable", "RowProblem", "write_long_csv", "write_season_geopackage",
           "plot_growth_curves", "main_trait", "check_season_outputs", "season_inputs",
           "TRAIT_GROUPS", "DEFAULT_PERCENTILES"]
