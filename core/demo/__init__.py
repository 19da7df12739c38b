"""The demo survey: a complete synthetic drone survey with known truth (see :mod:`.survey`).

Not imported by ``easyidp_toolbox.core``: ``from easyidp_toolbox.core.demo import
make_demo_survey``.
"""
from .field import NO_MESS, FieldMess
from .season import DemoSeason, make_demo_season
from .survey import SIZES, DemoSurvey, make_demo_survey

__all__ = ["make_demo_survey", "DemoSurvey", "SIZES", "make_demo_season", "DemoSeason",
           "FieldMess", "NO_MESS"]
